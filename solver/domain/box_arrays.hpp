// An RcbDomain's boxes as plain numbers that a kernel can read (docs/parallel.md, "On the GPU"):
// the owner of a point and its distance to each rank's box, the same answers, to the bit, as
// RcbDomain::owner and squared_distance give on the host, so that a rank's device decides the
// migration and the ghosts as its host would. Used by the CUDA decomposition
// (step/cuda/cuda_decomposition.cu); tested on the host against RcbDomain
// (tests/domain/test_box_arrays.cpp).
#pragma once

#include <vector>

#include "solver/core/hd.hpp"
#include "solver/domain/domain.hpp"

namespace talus {

// Box k's min x, y, z, then max x, y, z (6 numbers a box).
constexpr int kBoxNumbers = 6;

// The region's numbers (box 0), then each rank's box in rank order: 6 (ranks + 1) numbers.
inline std::vector<double> box_numbers(const RcbDomain& d) {
  std::vector<double> out;
  out.reserve(static_cast<std::size_t>(kBoxNumbers) * (d.ranks() + 1));
  const auto add = [&](const Box& b) {
    out.insert(out.end(), {b.min.x, b.min.y, b.min.z, b.max.x, b.max.y, b.max.z});
  };
  add(d.region());
  for (int r = 0; r < d.ranks(); ++r) add(d.box_of(r));
  return out;
}

// Box::contains: min <= x < max on every axis; NaN is in no box.
TALUS_HD inline bool box_holds(const double* b, double x, double y, double z) {
  return x >= b[0] && x < b[3] && y >= b[1] && y < b[4] && z >= b[2] && z < b[5];
}

// squared_distance(Box, x): each axis's distance outside the box, squared and summed in axis
// order, rounded as the host rounds each operation (no fused multiply-add on the device).
TALUS_HD inline double box_squared_distance(const double* b, double x, double y, double z) {
  const double v[3] = {x, y, z};
  double d2 = 0;
  for (int a = 0; a < 3; ++a) {
    // std::max({lo - v, 0.0, v - hi}) as the standard library takes it: the first, replaced by
    // each later one it is less than (so a NaN first stays, as on the host).
    double d = b[a] - v[a];
    if (d < 0.0) d = 0.0;
    const double above = v[a] - b[a + 3];
    if (d < above) d = above;
#ifdef __CUDA_ARCH__
    d2 = __dadd_rn(d2, __dmul_rn(d, d));
#else
    d2 += d * d;
#endif
  }
  return d2;
}

// RcbDomain::owner: -1 outside the region (numbers[0 .. 6)), else the rank whose box holds the
// point (the leaves of the bisection tile the region, each half-open as the tree's cuts are).
TALUS_HD inline int box_owner(const double* numbers, int ranks, double x, double y, double z) {
  if (!box_holds(numbers, x, y, z)) return -1;
  for (int r = 0; r < ranks; ++r)
    if (box_holds(numbers + kBoxNumbers * (r + 1), x, y, z)) return r;
  return -1;
}

}  // namespace talus
