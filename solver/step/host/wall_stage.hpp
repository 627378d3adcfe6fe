// Host driver of the wall contacts (paper §2.4): each wall located at the current time by its
// rigid motion (scene/wall_motion.hpp; a closed outlet's plate dropped when it opens) and its
// triangles placed (a moving wall's every step, a static wall's once), then per particle and
// wall, in wall-major order, one area-weighted contact (wall_kernels.hpp, templated on the
// scene's law: compute picks it once per call from contact/contact_laws.hpp); the volume laws'
// histories keyed by {global id, wall}; the contacts added to the particles after the pair
// contacts, in order. A particle's facets come from the wall's bin grid (walls/facet_grid.hpp,
// built once in the mesh's frame at construction), or, with WallSearch::brute_force, from
// testing every facet: the same contacts to the bit, at a cost that no longer grows with the
// wall's facets (benchmarks/bench_step_cpu.cpp measures both). A flat part of many facets (a
// cap's fan) is clipped as one plane where it holds the particle (walls/planar_patch.hpp).
//
// Threads (core/host_parallel.hpp): the (particle, wall) records are computed on all of them, each
// into its own slot of a wall-major array, then compacted serially in that order; the forces are
// added per particle (threads), its walls in wall order, after its pair contacts: the serial
// additions in the serial order, so the same bits for any thread count. The walls' totals are
// summed serially over the compacted contacts, in double.
#pragma once

#include <algorithm>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "solver/contact/contact_laws.hpp"
#include "solver/core/host_parallel.hpp"
#include "solver/scene/wall_meshes.hpp"
#include "solver/scene/wall_motion.hpp"
#include "solver/step/host/sorted_histories.hpp"
#include "solver/step/step_plan.hpp"
#include "solver/step/wall_kernels.hpp"
#include "solver/walls/facet_grid_build.hpp"
#include "solver/walls/planar_patch_build.hpp"

namespace talus {

template <class Real>
class WallContactStage {
 public:
  // `threads`: how many the host loops use (>= 1; HostStep resolves the default).
  WallContactStage(const Scene& scene, const std::vector<BodyProperties<Real>>& bodies,
                   int threads = 1, WallSearch search = WallSearch::grid)
      : scene_(scene), meshes_(make_wall_meshes(scene)), threads_(threads > 0 ? threads : 1) {
    const bool volume = with_contact_law(*scene.effects.contact,
                                         [](auto law) { return decltype(law)::kVolumeGeometry; });
    double max_radius = 0;  // the grid's cell size follows the largest bounding sphere
    for (const BodyProperties<Real>& b : bodies) {
      if (volume && b.sphere) {
        throw StepNotSupported(contact_place(scene) + ": the " + to_string(*scene.effects.contact) +
                               " model has no sphere-wall overlap; expected contact: {model: "
                               "linear, ...} for spheres with walls, got " +
                               to_string(*scene.effects.contact));
      }
      max_radius = std::max(max_radius, double(b.bounding_radius));
    }
    for (std::size_t w = 0; w < scene.walls.size(); ++w) {
      const WallMotion& m = scene.walls[w].motion;
      WallMotionData<Real> d;
      if (m.kind == WallMotion::Kind::rotation) {
        d.kind = 1;
        d.axis = Vec3<Real>(m.axis * (1 / norm(m.axis)));
        d.point = Vec3<Real>(m.point);
        d.angular_speed = Real(m.angular_speed());
      } else if (m.kind == WallMotion::Kind::translation) {
        d.kind = 2;
        d.velocity = Vec3<Real>(m.velocity);
      } else if (m.kind == WallMotion::Kind::oscillation) {
        d.kind = 2;  // a translation whose velocity locate() sets at each time
        oscillates_ = true;
      }
      motion_.push_back(d);
      plate_.push_back(meshes_[w].plate_triangles);
      const TriangleMesh& mesh = meshes_[w].mesh;
      if (search == WallSearch::grid)
        grids_.emplace_back(mesh.vertices, mesh.triangles, max_radius);
      patches_.push_back(find_planar_patches<Real>(mesh.vertices, mesh.triangles));
    }
    corners_.resize(scene.walls.size());
    placed_.assign(scene.walls.size(), false);
    facets_.resize(scene.walls.size());
    wall_force_.assign(scene.walls.size(), Vec3d());
    wall_torque_.assign(scene.walls.size(), Vec3d());
  }

  // Drops the plates of the outlets that are open at `time` (s), the start of a step.
  void open_outlets(double time) {
    for (std::size_t w = 0; w < meshes_.size(); ++w) {
      if (plate_[w] > 0 && !outlet_closed_at(scene_.walls[w], time)) plate_[w] = 0;
    }
  }

  // Where the walls are at `time` (s): each wall's present facets and rigid transform (facets()),
  // without placing corners (the CUDA step places them on the device).
  void locate(double time) {
    for (std::size_t w = 0; w < meshes_.size(); ++w) {
      const RigidTransform transform = wall_transform(scene_.walls[w].motion, time);
      WallFacets<Real>& f = facets_[w];
      f.corners = corners_[w].data();
      f.count = static_cast<int>(meshes_[w].mesh.triangles.size()) -
                (plate_[w] > 0 ? 0 : meshes_[w].plate_triangles);
      f.grid = grids_.empty() ? FacetGridView<Real>() : grids_[w].view();
      f.patches = patches_[w].data();
      f.patch_count = static_cast<int>(patches_[w].size());
      f.rotation = Quat<Real>(transform.rotation);
      f.translation = Vec3<Real>(transform.translation);
      const WallMotion& m = scene_.walls[w].motion;
      if (m.kind == WallMotion::Kind::oscillation)
        motion_[w].velocity = Vec3<Real>(m.direction * m.oscillation_speed(time));
    }
  }

  // locate(), and the triangles where the walls are at `time` (s): a moving wall's present ones
  // each call, a static wall's all once (they stay put; only its present count changes).
  void place(double time) {
    for (std::size_t w = 0; w < meshes_.size(); ++w) {
      if (placed_[w] && !moves(static_cast<int>(w))) continue;
      const TriangleMesh& mesh = meshes_[w].mesh;
      const int present = static_cast<int>(mesh.triangles.size()) -
                          (plate_[w] > 0 ? 0 : meshes_[w].plate_triangles);
      const int count = moves(static_cast<int>(w)) ? present : int(mesh.triangles.size());
      const RigidTransform transform = wall_transform(scene_.walls[w].motion, time);
      corners_[w].clear();
      for (int t = 0; t < count; ++t) {
        for (int k = 0; k < 3; ++k) {
          corners_[w].push_back(Vec3<Real>(transform.apply(mesh.vertices[mesh.triangles[t][k]])));
        }
      }
      placed_[w] = true;
    }
    locate(time);
  }

  // Record w * count + i for particle i and wall w; the touching ones compacted in that order. A
  // failed clipping throws after the loop, the lowest record first, as the serial loop did.
  void compute(const ParticleView<Real>& p, const PairLawTables<Real>& tables, Real spring_dt) {
    with_contact_law(*scene_.effects.contact,
                     [&](auto law) { compute<decltype(law)>(p, tables, spring_dt); });
  }

  // compute under the law Law (the scene's).
  template <class Law>
  void compute(const ParticleView<Real>& p, const PairLawTables<Real>& tables, Real spring_dt) {
    const int old_count = static_cast<int>(keys_.size());
    const long long count = p.count;
    records_.resize(facets_.size() * static_cast<std::size_t>(count));
    // Dynamic chunks: a particle near a wall clips facets, one far from it only queries the grid.
    parallel_for_dynamic(threads_, static_cast<long long>(records_.size()), 64, [&](long long k) {
      const int w = static_cast<int>(k / count), i = static_cast<int>(k % count);
      records_[k] =
          wall_contact<Law>(p, tables, i, w, scene_.walls[w].material, facets_[w], motion_[w],
                            spring_dt, keys_.data(), histories_.data(), old_count);
    });
    contacts_.clear();
    for (const WallContactRecord<Real>& r : records_) {
      if (r.degenerate) {
        throw std::runtime_error(scene_.file + ": particle " +
                                 std::to_string(p.global_id[r.particle]) + " against wall '" +
                                 scene_.walls[r.wall].name +
                                 "': a facet's clipping failed (section capacity)");
      }
      if (r.in_contact) contacts_.push_back(r);
    }
    if constexpr (Law::kTangentialHistory) sort_histories_by_key(contacts_, keys_, histories_);
  }

  // The forces on the particles (per particle, its walls in order: add_wall_force's additions),
  // and each wall's total force and torque about the origin (minus what its contacts gave the
  // particles), summed over the contacts in order.
  void accumulate(const ParticleView<Real>& p) {
    const int walls = static_cast<int>(corners_.size());
    parallel_for(threads_, p.count, [&](long long index) {
      const int i = static_cast<int>(index);
      for (int w = 0; w < walls; ++w) {
        const WallContactRecord<Real>& c = records_[static_cast<std::size_t>(w) * p.count + i];
        if (c.in_contact) add_wall_force(p, c);
      }
    });
    std::fill(wall_force_.begin(), wall_force_.end(), Vec3d());
    std::fill(wall_torque_.begin(), wall_torque_.end(), Vec3d());
    for (const WallContactRecord<Real>& c : contacts_) {
      wall_force_[c.wall] -= Vec3d(c.force);
      wall_torque_[c.wall] -= cross(Vec3d(c.point), Vec3d(c.force)) + Vec3d(c.couple);
    }
  }

  std::size_t contact_count() const { return contacts_.size(); }
  // Per wall, for the CUDA step (which uploads the grids and static corners once and places the
  // moving walls itself): its facets as locate() or place() left them (host pointers), its mesh
  // (the mesh frame = the world at t = 0), its grid (null with WallSearch::brute_force), whether
  // it moves, and its rigid motion.
  const WallFacets<Real>& facets(int w) const { return facets_.at(w); }
  const std::vector<Vec3<Real>>& corners(int w) const { return corners_.at(w); }
  const TriangleMesh& mesh(int w) const { return meshes_.at(w).mesh; }
  const FacetGrid<Real>* grid(int w) const { return grids_.empty() ? nullptr : &grids_.at(w); }
  const std::vector<PlanarPatch<Real>>& patches(int w) const { return patches_.at(w); }
  bool moves(int w) const { return scene_.walls.at(w).motion.kind != WallMotion::Kind::none; }
  // The touching records of the last compute, wall-major (the serial order).
  const std::vector<WallContactRecord<Real>>& contacts() const { return contacts_; }
  // The walls' motions for the contacts (an oscillating wall's velocity that of the last
  // locate's time), and whether some wall oscillates (its velocity changes with the time).
  const std::vector<WallMotionData<Real>>& motions() const { return motion_; }
  bool oscillates() const { return oscillates_; }
  // The history store (the touching contacts of the last evaluation, sorted by key), and setting
  // it (a restart).
  const std::vector<PairKey>& history_keys() const { return keys_; }
  const std::vector<ContactHistoryData<Real>>& histories() const { return histories_; }
  void set_histories(std::vector<PairKey> keys, std::vector<ContactHistoryData<Real>> histories) {
    keys_ = std::move(keys);
    histories_ = std::move(histories);
  }
  const Vec3d& wall_force(int w) const { return wall_force_.at(w); }
  const Vec3d& wall_torque(int w) const { return wall_torque_.at(w); }
  std::size_t allocated_bytes() const {
    std::size_t bytes =
        (records_.capacity() + contacts_.capacity()) * sizeof(WallContactRecord<Real>) +
        keys_.capacity() * sizeof(PairKey) +
        histories_.capacity() * sizeof(ContactHistoryData<Real>);
    for (const auto& c : corners_) bytes += c.capacity() * sizeof(Vec3<Real>);
    for (const FacetGrid<Real>& g : grids_) bytes += g.bytes();
    return bytes;
  }

 private:
  const Scene& scene_;
  std::vector<WallMesh> meshes_;
  std::vector<WallMotionData<Real>> motion_;
  bool oscillates_ = false;
  std::vector<int> plate_;  // per wall: its closed plate's triangles while present, else 0
  int threads_;
  std::vector<FacetGrid<Real>> grids_;  // per wall, in its mesh frame; empty: brute force
  std::vector<std::vector<PlanarPatch<Real>>> patches_;  // per wall, in its mesh frame
  std::vector<std::vector<Vec3<Real>>> corners_;
  std::vector<bool> placed_;  // whether a static wall's corners are placed
  std::vector<WallFacets<Real>> facets_;
  std::vector<WallContactRecord<Real>> records_, contacts_;  // per (wall, particle); touching
  std::vector<PairKey> keys_;
  std::vector<ContactHistoryData<Real>> histories_;
  std::vector<Vec3d> wall_force_, wall_torque_;
};

}  // namespace talus
