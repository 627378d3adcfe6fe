// The geometry kernels on the GPU against the same kernels on the host: one source compiled twice
// must give the same numbers. Label `gpu`; every test skips with the reason where no GPU is
// present. Tolerance: the device contracts a*b+c into fused multiply-adds where the host does
// not, so single operations differ in the last bit and results by ~1e-15 relative; 1e-12 is
// the issue's bound and leaves three orders of magnitude. Shallow overlaps amplify the
// difference by L/d (see test_overlap_oracle.cpp), so volumes below 1e-6 of the body are
// compared absolutely at 1e-15 of the body's volume.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "benchmarks/overlap_batch/overlap_batch.hpp"
#include "solver/core/cuda_device.hpp"
#include "solver/core/device_buffer.hpp"
#include "solver/geometry/device_shape.cuh"
#include "solver/geometry/gjk.hpp"
#include "solver/geometry/simple_contact.hpp"
#include "solver/geometry/wall_clip.hpp"
#include "tests/geometry/overlap_test_util.hpp"
#include "tests/support/random_poses.hpp"

namespace talus::testing {
namespace {

#define REQUIRE_GPU()                                      \
  do {                                                     \
    std::string why;                                       \
    if (!cuda_device_available(&why)) GTEST_SKIP() << why; \
  } while (0)

struct PoseList {
  std::vector<Posed> a, b;
};

PoseList random_pairs(const TestShape& sa, const TestShape& sb, int count, unsigned seed) {
  std::mt19937_64 rng(seed);
  PoseList list;
  for (int k = 0; k < count; ++k) {
    const auto pair = random_overlapping_pair(rng, sa.shape.bounding_radius,
                                              sb.shape.bounding_radius, 0.0, k % 2 ? 0.1 : 0.7);
    list.a.push_back(pair.a);
    list.b.push_back(pair.b);
  }
  return list;
}

void compare_overlap(const TestShape& sa, const TestShape& sb, const PoseList& poses) {
  OverlapBatchGpu<double> batch(sa.view(), sb.view());
  batch.set_poses(poses.a, poses.b);
  batch.run();
  const auto device = batch.results();
  ASSERT_EQ(device.size(), poses.a.size());
  const double scale_v = std::min(sa.shape.volume, sb.shape.volume);
  const double scale_s = std::pow(scale_v, 2.0 / 3.0);
  int overlapping = 0;
  for (std::size_t k = 0; k < device.size(); ++k) {
    const auto host = overlap(sa, poses.a[k], sb, poses.b[k]);
    const auto& gpu = device[k];
    ASSERT_FALSE(gpu.workspace_overrun) << k;
    if (host.volume > 1e-6 * scale_v) {
      ++overlapping;
      ASSERT_EQ(gpu.status, host.status) << k;
      ASSERT_NEAR(gpu.volume, host.volume, 1e-12 * host.volume) << k;
      ASSERT_LE(norm(gpu.vector_area - host.vector_area), 1e-12 * scale_s) << k;
      ASSERT_LE(norm(gpu.centroid - host.centroid), 1e-12 * std::cbrt(scale_v)) << k;
    } else {
      ASSERT_NEAR(gpu.volume, host.volume, 1e-15 * scale_v) << k;
    }
  }
  EXPECT_GT(overlapping, int(device.size() / 10));
}

TEST(GpuOverlap, BuiltinPairsAgreeWithTheHostInDouble) {
  REQUIRE_GPU();
  const auto specs = builtin_specs();
  for (std::size_t i = 0; i < specs.size(); ++i) {
    const TestShape a(specs[i]), b(specs[(i + 3) % specs.size()]);
    SCOPED_TRACE(specs[i] + " vs " + specs[(i + 3) % specs.size()]);
    compare_overlap(a, b, random_pairs(a, b, 4000, 17 + unsigned(i)));
  }
}

TEST(GpuOverlap, HardCasesAgreeWithTheHost) {
  REQUIRE_GPU();
  const TestShape cube("cube:0.017320508075688773"), cyl("cylinder:0.008,0.0053");
  PoseList poses;
  const Posed origin = input_frame_pose(cube.shape, {});
  const double side = 0.01;
  for (const Vec3d offset : {Vec3d(0.003, 0, side - 1e-5), Vec3d(side, 0, 0), Vec3d(side, side, 0),
                             Vec3d(0.002, -0.001, side * (1 - 1e-12)), Vec3d(0, 0, 0)}) {
    poses.a.push_back(origin);
    poses.b.push_back(input_frame_pose(cube.shape, offset));
  }
  compare_overlap(cube, cube, poses);
  PoseList turned;
  for (const Vec3d axis : {Vec3d(0, 0, 1), Vec3d(1, 0, 0), Vec3d(0.6, 0.8, 0)}) {
    turned.a.push_back(Posed{{0.01, 0.02, 0.03}, Quatd()});
    turned.b.push_back(Posed{{0.01, 0.02, 0.03}, Quatd::from_axis_angle(axis, 1e-9)});
  }
  compare_overlap(cyl, cyl, turned);
}

// The batch's two paths (OverlapBatchPath) build each pair's polytope with the same arithmetic:
// the phased one culls in a kernel of its own, sorts the pairs by kept planes, runs one polytope
// kernel per workspace size and the vertex enumeration for the fewest planes, and defers what a
// workspace cannot hold; the whole one runs overlap_polyhedra in one thread. The results must be
// identical, bit for bit, in every culling variant. Deep pairs (depth up to 0.95 of the radii)
// keep more planes than the smallest workspaces hold and so exercise the larger buckets and the
// deferral; random_pairs-like poses include separated pairs, decided in the culling phase.
template <class Real>
void expect_identical_paths(const ConvexView<Real>& a, const ConvexView<Real>& b,
                            const std::vector<Pose<Real>>& pa, const std::vector<Pose<Real>>& pb,
                            int& many_planes, int& enumerated) {
  OverlapBatchGpu<Real> batch(a, b);
  batch.set_poses(pa, pb);
  for (const char* variant : {"faces", "planes", "naive", "vertices"}) {
    SCOPED_TRACE(variant);
    const OverlapOptions options = overlap_options_named(variant);
    batch.run(options, OverlapBatchPath::whole);
    const auto reference = batch.results();
    batch.run(options, OverlapBatchPath::phased);
    const auto other = batch.results();
    ASSERT_EQ(other.size(), reference.size());
    for (std::size_t k = 0; k < other.size(); ++k) {
      const auto &r = reference[k], &o = other[k];
      ASSERT_EQ(int(o.status), int(r.status)) << k;
      ASSERT_EQ(o.volume, r.volume) << k;
      ASSERT_EQ(o.depth_hint, r.depth_hint) << k;
      ASSERT_EQ(o.hull_points, r.hull_points) << k;
      ASSERT_EQ(o.workspace_overrun, r.workspace_overrun) << k;
      ASSERT_EQ(o.enumerated, r.enumerated) << k;
      for (int c = 0; c < 3; ++c) {
        ASSERT_EQ(o.vector_area[c], r.vector_area[c]) << k;
        ASSERT_EQ(o.centroid[c], r.centroid[c]) << k;
        ASSERT_EQ(o.surface_moment[c], r.surface_moment[c]) << k;
      }
    }
    for (const auto& r : reference) {
      many_planes += r.hull_points > kEnumerationPlanes;  // a hull, not the enumeration
      enumerated += r.enumerated;
    }
  }
}

TEST(GpuOverlap, PhasedAndWholePathsGiveIdenticalResults) {
  REQUIRE_GPU();
  for (const char* spec : {"dodecahedron:0.01", "cylinder:0.008,0.0053"}) {
    SCOPED_TRACE(spec);
    const TestShape shape(spec);
    std::mt19937_64 rng(31);
    PoseList poses;
    for (int k = 0; k < 3000; ++k) {
      const double deepest = k % 3 == 0 ? 0.95 : 0.1;
      const auto pair = random_overlapping_pair(rng, shape.shape.bounding_radius,
                                                shape.shape.bounding_radius, 0.0, deepest);
      poses.a.push_back(pair.a);
      poses.b.push_back(pair.b);
    }
    int many_planes = 0, enumerated = 0;
    expect_identical_paths(shape.view(), shape.view(), poses.a, poses.b, many_planes, enumerated);
    std::vector<Pose<float>> fa, fb;
    for (std::size_t k = 0; k < poses.a.size(); ++k) {
      fa.push_back(to_float(poses.a[k]));
      fb.push_back(to_float(poses.b[k]));
    }
    expect_identical_paths(shape.view_f(), shape.view_f(), fa, fb, many_planes, enumerated);
    // Pairs whose polytope has more than 8 faces went to the hull's buckets, and the
    // "vertices" variant's shallow pairs to the vertex enumeration (with the pairs it declines
    // deferred): 751 of the cylinder's double and float pairs on the H100 (a third of the poses
    // are deep, and its caps keep more than 8 planes).
    EXPECT_GT(many_planes, 0);
    EXPECT_GT(enumerated, 500);
  }
}

// Float on the device against float on the host: the same float arithmetic up to contraction,
// whose effect is ~1e-7 relative, amplified by L/d for shallow overlaps: 1e-4 on overlaps deeper
// than 1e-3 of the body.
TEST(GpuOverlap, FloatAgreesWithTheHostFloat) {
  REQUIRE_GPU();
  const TestShape a("dodecahedron:0.01"), b("mineral:0.01");
  const auto poses = random_pairs(a, b, 4000, 5);
  std::vector<Pose<float>> fa, fb;
  for (std::size_t k = 0; k < poses.a.size(); ++k) {
    fa.push_back(to_float(poses.a[k]));
    fb.push_back(to_float(poses.b[k]));
  }
  OverlapBatchGpu<float> batch(a.view_f(), b.view_f());
  batch.set_poses(fa, fb);
  batch.run();
  const auto device = batch.results();
  const double scale_v = std::min(a.shape.volume, b.shape.volume);
  int compared = 0;
  for (std::size_t k = 0; k < device.size(); ++k) {
    const auto host = overlap(a.view_f(), fa[k], b.view_f(), fb[k]);
    if (host.volume > 1e-3 * scale_v) {
      ++compared;
      ASSERT_NEAR(device[k].volume, host.volume, 1e-4 * host.volume) << k;
    }
  }
  EXPECT_GT(compared, 1000);
}

__global__ void gjk_kernel(ConvexView<double> a, ConvexView<double> b, const Posed* pa,
                           const Posed* pb, int n, int* out) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i < n) out[i] = gjk_intersect(a, pa[i], b, pb[i]).intersecting ? 1 : 0;
}

__global__ void simple_kernel(ConvexView<double> a, ConvexView<double> b, const Posed* pa,
                              const Posed* pb, int n, SimpleContact<double>* out) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i < n) out[i] = polyhedron_polyhedron_contact(a, pa[i], b, pb[i]);
}

__global__ void wall_kernel(ConvexView<double> a, const Posed* pa, int n, Vec3d t0, Vec3d t1,
                            Vec3d t2, WallContact<double>* out) {
  const int i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i < n) out[i] = clip_against_triangle(a, pa[i], t0, t1, t2);
}

template <class T>
std::vector<T> download(const DeviceBuffer<T>& buffer) {
  std::vector<T> host;
  buffer.download(host);
  return host;
}

TEST(GpuGjk, AgreesWithTheHost) {
  REQUIRE_GPU();
  const TestShape a("icosahedron:0.009"), b("corn:0.01");
  const auto poses = random_pairs(a, b, 20000, 9);
  DeviceShape<double> da(a.view()), db(b.view());
  DeviceBuffer<Posed> pa, pb;
  pa.upload(poses.a);
  pb.upload(poses.b);
  DeviceBuffer<int> out(poses.a.size());
  const int n = int(poses.a.size());
  gjk_kernel<<<(n + 127) / 128, 128>>>(da.view, db.view, pa.data(), pb.data(), n, out.data());
  TALUS_CUDA_LAUNCH_CHECK();
  const auto device = download(out);
  int mismatches = 0, intersecting = 0;
  for (int k = 0; k < n; ++k) {
    const bool host = gjk_intersect(a.view(), poses.a[k], b.view(), poses.b[k]).intersecting;
    mismatches += host != bool(device[k]);
    intersecting += host;
  }
  // Only a pair within round-off of touching can be decided differently by contracted arithmetic.
  EXPECT_EQ(mismatches, 0);
  EXPECT_GT(intersecting, n / 10);
}

TEST(GpuSimpleContact, AgreesWithTheHost) {
  REQUIRE_GPU();
  const TestShape a("dodecahedron:0.01"), b("cuboid:0.004,0.006,0.009");
  const auto poses = random_pairs(a, b, 4000, 10);
  DeviceShape<double> da(a.view()), db(b.view());
  DeviceBuffer<Posed> pa, pb;
  pa.upload(poses.a);
  pb.upload(poses.b);
  DeviceBuffer<SimpleContact<double>> out(poses.a.size());
  const int n = int(poses.a.size());
  simple_kernel<<<(n + 127) / 128, 128>>>(da.view, db.view, pa.data(), pb.data(), n, out.data());
  TALUS_CUDA_LAUNCH_CHECK();
  const auto device = download(out);
  int touching = 0;
  for (int k = 0; k < n; ++k) {
    const auto host = polyhedron_polyhedron_contact(a.view(), poses.a[k], b.view(), poses.b[k]);
    ASSERT_EQ(host.touching, device[k].touching) << k;
    if (!host.touching) continue;
    ++touching;
    ASSERT_NEAR(device[k].depth, host.depth, 1e-12 * 0.01) << k;
    ASSERT_LT(norm(device[k].normal - host.normal), 1e-9) << k;
  }
  EXPECT_GT(touching, n / 10);
}

TEST(GpuWallClip, AgreesWithTheHost) {
  REQUIRE_GPU();
  const TestShape a("mineral:0.01");
  std::mt19937_64 rng(12);
  std::vector<Posed> poses;
  for (int k = 0; k < 4000; ++k) {
    Posed p = random_pose(rng, 0.004);
    p.position.z = 0.006 * (double(k) / 4000 - 0.5);  // from well below to above the plane
    poses.push_back(p);
  }
  const Vec3d t0(-0.004, -0.004, 0), t1(0.006, -0.003, 0), t2(-0.002, 0.005, 0);
  DeviceShape<double> da(a.view());
  DeviceBuffer<Posed> pa;
  pa.upload(poses);
  DeviceBuffer<WallContact<double>> out(poses.size());
  const int n = int(poses.size());
  wall_kernel<<<(n + 127) / 128, 128>>>(da.view, pa.data(), n, t0, t1, t2, out.data());
  TALUS_CUDA_LAUNCH_CHECK();
  const auto device = download(out);
  int overlapping = 0;
  const double area_scale = 0.01 * 0.01, volume_scale = a.shape.volume;
  for (int k = 0; k < n; ++k) {
    const auto host = clip_against_triangle(a.view(), poses[k], t0, t1, t2);
    ASSERT_EQ(int(host.status), int(device[k].status)) << k;
    overlapping += host.status == WallContactStatus::overlapping;
    ASSERT_NEAR(device[k].overlap_area, host.overlap_area, 1e-12 * area_scale) << k;
    ASSERT_NEAR(device[k].volume_below, host.volume_below, 1e-12 * volume_scale) << k;
    ASSERT_NEAR(device[k].depth, host.depth, 1e-12 * 0.01) << k;
  }
  EXPECT_GT(overlapping, n / 10);
}

}  // namespace
}  // namespace talus::testing
