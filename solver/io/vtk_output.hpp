// ParaView output (outputs.vtk; format in docs/scenes.md, "Output files"), the same for every
// solver and backend: built from the trajectory rows of the step and from the scene. In the
// directory, per output step,
//   particles_<step>.vtp  surfaces: each particle's polygons (its template's faces) posed at
//                         position + R(q) vertex, cell data id, template, velocity,
//                         angular_velocity; points: one vertex cell per particle, point data id,
//                         template, orientation (w, x, y, z), velocity, angular_velocity,
//                         bounding_radius;
//   walls_<step>.vtp      every wall's present triangles where the wall is at the frame's time,
//                         cell data wall (its index in the scene's list); written again only when
//                         the walls have changed (a moving wall, an outlet that opened);
// and particles.pvd and walls.pvd, the time series. Each file goes through a temporary name and a
// rename, and the collections are rewritten after each frame's files, so an interrupted run leaves
// a valid series of the frames it completed.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "solver/io/trajectory.hpp"
#include "solver/io/vtk_xml.hpp"
#include "solver/scene/scene.hpp"
#include "solver/scene/wall_meshes.hpp"

namespace talus {

// The particle count up to which `particles` defaults to surfaces. A dodecahedron's surface takes
// about 2.4 kB of base64 per frame (20 points, 12 pentagons with their cell data), a point about
// 0.16 kB: 10^4 particles give frames of ~25 MB as surfaces, which ParaView draws interactively;
// beyond that the points (glyphs) are the practical view.
constexpr std::size_t kVtkSurfaceParticleLimit = 10000;

// The scene's choice, else surfaces when the run can hold at most kVtkSurfaceParticleLimit
// particles: `initial_particles` plus every particle its feeds may insert.
VtkParticles vtk_particles_for(const Scene& scene, std::size_t initial_particles);

// A template's surface in its body frame: polygons over its vertices, counter-clockwise seen from
// outside. A polyhedron: its merged faces. A sphere: a latitude-longitude polyhedron of
// kSphereBands bands and kSphereSegments segments with its vertices on the sphere (two polar
// fans of triangles, quadrilaterals between).
constexpr int kSphereBands = 6, kSphereSegments = 12;
struct TemplateSurface {
  std::vector<Vec3d> vertices;
  std::vector<std::vector<int>> faces;
};
TemplateSurface template_surface(const ParticleTemplate& t);

// The particles of one frame as surfaces (`surfaces` indexed by template id) or as points.
VtkPolyData particle_surfaces(const std::vector<TemplateSurface>& surfaces,
                              const std::vector<TrajectoryRow>& rows);
VtkPolyData particle_points(const Scene& scene, const std::vector<TrajectoryRow>& rows);

// The walls' present triangles at `time` (s): each mesh of make_wall_meshes moved by its wall's
// rigid motion, a closed outlet's plate only while outlet_closed_at says so.
VtkPolyData wall_polygons(const Scene& scene, const std::vector<WallMesh>& meshes, double time);

class VtkSeriesWriter {
 public:
  // Creates `directory` when missing (std::runtime_error naming it otherwise).
  VtkSeriesWriter(const Scene& scene, std::string directory, VtkParticles particles);

  // The frame's files, then the collections listing every frame so far. Throws
  // std::runtime_error naming the file that cannot be written.
  void write_frame(long long step, double time, const std::vector<TrajectoryRow>& rows);

  const std::string& directory() const { return directory_; }
  VtkParticles particles() const { return particles_; }

  // What the series needs to go on (the frames the collections list, the last walls file and
  // what it held) as text; restore() on a writer of the same scene and directory continues the
  // collections as this one would (a restart). Throws std::runtime_error when the text is not a
  // saved state.
  std::string save() const;
  void restore(const std::string& state);

 private:
  void write_walls(long long step, double time);

  const Scene& scene_;
  std::string directory_;
  VtkParticles particles_;
  std::vector<TemplateSurface> surfaces_;  // by template id (surfaces only)
  std::vector<WallMesh> meshes_;           // at t = 0
  std::vector<int> written_triangles_;     // per wall, in the last walls file (-1: none yet)
  std::string walls_file_;                 // the last walls file
  std::vector<PvdEntry> particle_frames_, wall_frames_;
};

}  // namespace talus
