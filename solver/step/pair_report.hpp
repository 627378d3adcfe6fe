// The message of a pair whose contact geometry could not be computed: the scene file, both
// particles' ids and templates, and their poses in full precision (position and orientation),
// so that the failing overlap can be replayed on its own (overlap_polyhedra with the two poses)
// from the message alone. Host code; the CUDA step downloads the two particles' values first.
#pragma once

#include <cstdio>
#include <string>

#include "solver/scene/scene.hpp"

namespace talus {

struct ParticlePoseReport {
  long long id = -1;
  int template_id = -1;
  double position[3] = {0, 0, 0};
  double orientation[4] = {1, 0, 0, 0};  // w, x, y, z
};

// Particle i of a host-readable view.
template <class View>
ParticlePoseReport pose_report(const View& p, int i) {
  ParticlePoseReport r;
  r.id = p.global_id ? p.global_id[i] : i;
  r.template_id = p.template_id ? p.template_id[i] : -1;
  const auto x = p.position.get(i);
  const auto q = p.orientation.get(i);
  r.position[0] = double(x.x), r.position[1] = double(x.y), r.position[2] = double(x.z);
  r.orientation[0] = double(q.w), r.orientation[1] = double(q.x);
  r.orientation[2] = double(q.y), r.orientation[3] = double(q.z);
  return r;
}

inline std::string describe_pose(const Scene& scene, const ParticlePoseReport& r) {
  const bool named = r.template_id >= 0 && r.template_id < static_cast<int>(scene.templates.size());
  char buffer[256];
  std::snprintf(buffer, sizeof buffer,
                " at (%.17g, %.17g, %.17g), orientation (%.17g, %.17g, %.17g, %.17g)",
                r.position[0], r.position[1], r.position[2], r.orientation[0], r.orientation[1],
                r.orientation[2], r.orientation[3]);
  return "particle " + std::to_string(r.id) + " (template '" +
         (named ? scene.templates[r.template_id].name : std::string("?")) + "')" + buffer;
}

inline std::string degenerate_pair_message(const Scene& scene, const ParticlePoseReport& a,
                                           const ParticlePoseReport& b) {
  return scene.file + ": particles " + std::to_string(a.id) + " and " + std::to_string(b.id) +
         ": the contact geometry is degenerate (a sphere inside another, or an overlap the "
         "workspace cannot hold); " +
         describe_pose(scene, a) + "; " + describe_pose(scene, b);
}

}  // namespace talus
