// Which process owns which part of space (docs/design.md, "Domains"): the seam on which a domain
// decomposition over many GPUs stands. A Domain says which rank owns a point (or that no rank
// does: the point has left the simulated region, and its particle is removed), the box this rank
// owns, how far beyond it the rank must see other ranks' particles (the halo: the broad phase's
// reach, 2 r_max + skin), and how the ranks combine one number each (a probe's sum or maximum).
// The steps, their broad phase and feeds, the probes and the writers take the local domain rather
// than the global extent of the particles.
//
// One process today: SingleDomain owns the scene's `domain` box (or all of space) as rank 0 of 1.
// SlabDomain cuts a bounded box into equal slabs along one axis, one a rank: the first
// decomposition; its tests show the seams (every point owned once, feeds split without loss).
#pragma once

#include <limits>
#include <memory>
#include <vector>

#include "solver/core/vec3.hpp"

namespace talus {

struct Scene;

// An axis-aligned box, min <= max on every axis; the default holds all of space.
struct Box {
  Vec3d min{-std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
            -std::numeric_limits<double>::infinity()};
  Vec3d max{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
            std::numeric_limits<double>::infinity()};

  // Finite on every axis.
  bool bounded() const;
  // min <= x < max on every axis (half-open, so that adjacent boxes share no point); NaN is in no
  // box.
  bool contains(const Vec3d& x) const;
  // Grown by `margin` on every side.
  Box expanded(double margin) const;
};

class Domain {
 public:
  virtual ~Domain() = default;
  virtual int rank() const = 0;
  virtual int ranks() const = 0;
  // The rank that owns point x; -1 when none does (x is outside the simulated region).
  virtual int owner(const Vec3d& x) const = 0;
  // The region this rank owns (the union over ranks is the simulated region).
  virtual Box local_box() const = 0;
  // How far beyond local_box() a particle can still touch one of this rank's, m: the largest
  // contact reach, 2 r_max + skin.
  virtual double halo_width() const = 0;
  // A number from every rank combined (one process: the number itself).
  virtual double sum(double local) const = 0;
  virtual double max(double local) const = 0;

  bool owns(const Vec3d& x) const { return owner(x) == rank(); }
  // The box this rank's particles and the others' it must see lie in: local_box() grown by the
  // halo. The broad phase puts its grid's origin at its lowest corner when it is bounded.
  Box reach_box() const { return local_box().expanded(halo_width()); }
};

// One process owning all of `region` (points outside it are owned by none).
class SingleDomain final : public Domain {
 public:
  explicit SingleDomain(const Box& region = Box(), double halo_width = 0)
      : region_(region), halo_(halo_width) {}
  int rank() const override { return 0; }
  int ranks() const override { return 1; }
  int owner(const Vec3d& x) const override { return region_.contains(x) ? 0 : -1; }
  Box local_box() const override { return region_; }
  double halo_width() const override { return halo_; }
  double sum(double local) const override { return local; }
  double max(double local) const override { return local; }

 private:
  Box region_;
  double halo_;
};

// A bounded `region` cut along `axis` (0, 1, 2) into `ranks` slabs of equal width, seen from
// `rank`. Its sum and max are this rank's number alone: the communication between ranks comes
// with the MPI layer; SingleDomain is what runs today.
class SlabDomain final : public Domain {
 public:
  // Throws std::invalid_argument for an unbounded or empty region, a bad axis or rank.
  SlabDomain(const Box& region, int axis, int ranks, int rank, double halo_width);
  int rank() const override { return rank_; }
  int ranks() const override { return ranks_; }
  int owner(const Vec3d& x) const override;
  Box local_box() const override;
  double halo_width() const override { return halo_; }
  double sum(double local) const override { return local; }
  double max(double local) const override { return local; }

 private:
  Box region_;
  int axis_, ranks_, rank_;
  double halo_;
};

// A region cut by recursive coordinate bisection (docs/parallel.md) into `ranks` boxes holding
// about equal numbers of `points`: the ranks split in two halves (the lower half the smaller),
// the points at the coordinate along the axis of their widest extent that gives each half its
// share, and so on down to one rank a box. Every rank builds it from the same points and gets
// the same cuts, to the bit. sum and max go through `comm` (null: this rank's number alone).
class Communicator;
class RcbDomain final : public Domain {
 public:
  // Throws std::invalid_argument for a bad rank or rank count.
  RcbDomain(const std::vector<Vec3d>& points, const Box& region, int ranks, int rank,
            double halo_width, const Communicator* comm = nullptr);
  int rank() const override { return rank_; }
  int ranks() const override { return static_cast<int>(boxes_.size()); }
  int owner(const Vec3d& x) const override;
  Box local_box() const override { return boxes_[rank_]; }
  double halo_width() const override { return halo_; }
  double sum(double local) const override;
  double max(double local) const override;
  // Rank r's box.
  const Box& box_of(int r) const { return boxes_.at(r); }
  const Box& region() const { return region_; }

 private:
  struct Node {
    int axis = 0;
    double cut = 0;
    int below = -1, above = -1;  // children (node indices); -1 -1 for a leaf
    int rank = -1;               // a leaf's rank
  };
  int build(std::vector<Vec3d> points, const Box& box, int first_rank, int ranks);

  Box region_;
  int rank_;
  double halo_;
  const Communicator* comm_;
  std::vector<Node> nodes_;
  std::vector<Box> boxes_;
};

// The squared distance from x to box b (0 inside; infinite faces are never reached).
double squared_distance(const Box& b, const Vec3d& x);

// The scene's reach: 2 r_max + skin, with the skin as the CUDA step's pair list takes it (the
// scene's, else a tenth of the largest bounding diameter). m.
double scene_halo_width(const Scene& scene);
// The domain a run of `scene` in one process has: its `domain` box (all of space when it has
// none) and its halo.
std::unique_ptr<Domain> make_scene_domain(const Scene& scene);

}  // namespace talus
