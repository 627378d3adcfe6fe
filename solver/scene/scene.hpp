// A scene as plain data: what a YAML scene file asks for, checked and with names resolved to
// indices. Both solvers (production and reference) read scenes through this one library;
// docs/scenes.md documents the file format key by key. SI units throughout.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "solver/core/quat.hpp"
#include "solver/domain/domain.hpp"
#include "solver/shape/mesh_io.hpp"
#include "solver/shape/shape.hpp"

namespace talus {

// Where an item was written, so that a solver can point a later message (a fill that cannot be
// placed, a backend that lacks an effect) back at the scene file.
struct SourceRef {
  std::string file;
  int line = 0;  // 1-based; 0 when unknown
  int column = 0;
  std::string key;  // e.g. "particles[2].random"
  // "scene.yaml:12:5: particles[2].random"
  std::string where() const;
};

struct Material {
  std::string name;
  double density = 0;         // kg/m^3, > 0
  double youngs_modulus = 0;  // E, Pa, > 0 (paper Eqs. 13, 19)
  double poisson_ratio = 0;   // nu, in [0, 0.5) (Eq. 19)
  double friction = 0;        // Coulomb mu, >= 0 (Eq. 17)
  double restitution = 1;     // epsilon, in (0, 1] (Eqs. 15, 20)
  SourceRef source;
};

// Friction and restitution for one pair of materials, replacing the default combination.
struct MaterialPair {
  int material_a = -1;  // indices into Scene::materials, material_a <= material_b
  int material_b = -1;
  std::optional<double> friction;
  std::optional<double> restitution;
  SourceRef source;
};

enum class ParticleShapeKind { polyhedron, sphere };

struct ParticleTemplate {
  std::string name;
  ParticleShapeKind kind = ParticleShapeKind::polyhedron;
  int material = -1;  // index into Scene::materials
  // Polyhedra: the spec as written, and the one given to make_shape (a mesh path resolved
  // against the scene file's directory, followed by ":scale" when a scale was given).
  std::string shape_spec;
  std::string resolved_spec;
  std::string mesh_file;       // resolved path of a mesh file; empty for a built-in shape
  double mesh_scale = 1;       // file units to metres
  ShapeTemplate shape;         // polyhedra: built by make_shape when the scene is loaded
  double sphere_radius = 0;    // spheres, m
  double volume = 0;           // m^3
  double bounding_radius = 0;  // m, about the centroid
  SourceRef source;
};

// One particle placed by the scene (the explicit list). Orientation: body -> world.
struct ParticleState {
  int template_index = -1;
  Vec3d position;  // centroid, m
  Quatd orientation;
  Vec3d velocity;          // m/s
  Vec3d angular_velocity;  // rad/s, world frame
  SourceRef source;
};

enum class RegionKind { box, cylinder };

struct Region {
  RegionKind kind = RegionKind::box;
  Vec3d box_min, box_max;         // box: min < max on every axis
  Vec3d base;                     // cylinder: centre of the bottom disc
  Vec3d axis = Vec3d(0, 0, 1);    // cylinder: unit, from the bottom disc to the top one
  double radius = 0, height = 0;  // cylinder
  double volume() const;
};

// Particles at the points min + spacing * (i + 1/2) of a box, as many as fit.
struct LatticeRequest {
  int template_index = -1;
  Region region;  // always a box
  Vec3d spacing;  // m per axis, at least the template's bounding diameter
  Vec3d velocity;
  bool random_orientation = false;
  std::uint64_t seed = 0;  // for the random orientations
  SourceRef source;
};

// `count` particles placed at random in a region, bounding spheres inside it and not
// overlapping each other or anything placed before; the solver does the placing.
struct RandomFillRequest {
  int template_index = -1;
  Region region;
  long long count = 0;         // resolved from volume_fraction when that was given
  double volume_fraction = 0;  // as written; 0 when a count was given
  Vec3d velocity;
  bool random_orientation = true;
  std::uint64_t seed = 0;
  SourceRef source;
};

// Particles inserted during the run at `rate` per second, from `start` to `stop`, at random
// non-overlapping places in the region.
struct FeedRequest {
  int template_index = -1;
  Region region;
  double rate = 0;             // particles per second
  double start = 0, stop = 0;  // s
  Vec3d velocity;
  bool random_orientation = true;
  std::uint64_t seed = 0;
  SourceRef source;
};

struct WallMotion {
  enum class Kind { none, rotation, translation, oscillation };
  Kind kind = Kind::none;
  Vec3d axis = Vec3d(0, 0, 1);  // rotation: unit axis through `point`, right-handed
  Vec3d point;
  double rpm = 0;                // revolutions per minute; negative turns the other way
  Vec3d velocity;                // translation, m/s
  double angular_speed() const;  // rad/s
  // Oscillation (a shaken or tapped container): a translation along the unit `direction` by a
  // raised cosine, d(t) = amplitude (1 - cos(2 pi frequency (t - start))) for start < t <
  // start + cycles / frequency (without end when cycles is 0), zero before and after: the wall
  // leaves its rest position and comes back to it, its speed zero at each cycle's ends (no
  // impulse at the start or the stop), its peak acceleration amplitude (2 pi frequency)^2 (the
  // tapping intensity Gamma is that over g).
  Vec3d direction = Vec3d(0, 0, 1);
  double amplitude = 0;  // m (the wall's excursion is twice this)
  double frequency = 0;  // Hz
  double start = 0;      // s
  int cycles = 0;        // whole cycles, 0: without end
  // d(t) and its rate, m and m/s (zero unless an oscillation in progress).
  double oscillation_displacement(double time) const;
  double oscillation_speed(double time) const;
};

// A triangle mesh read from a file; world = translation + R(rotation) (scale * file).
struct MeshWall {
  std::string file;  // resolved against the scene file's directory
  double scale = 1;
  Quatd rotation;
  Vec3d translation;
  TriangleMesh mesh;  // as read, before the transform
};
// A square of side `size` centred at `point`; particles stay on the side `normal` points to.
struct PlaneWall {
  Vec3d point, normal;
  double size = 0;
};
// A closed box holding particles inside (open_top: no face at max.z).
struct BoxWall {
  Vec3d min, max;
  bool open_top = false;
};
// The axial walls below hold particles inside. `base` is the centre of the bottom circle,
// `axis` the unit direction from bottom to top, `segments` the sides of the polygon that
// approximates each circle (the wall mesh's resolution).
struct CylinderWall {
  Vec3d base, axis;
  double radius = 0, height = 0;
  bool bottom_cap = false, top_cap = false;
  int segments = 0;
};
// A closed cylinder centred at `center` (both ends capped), usually rotating about its axis.
struct DrumWall {
  Vec3d center, axis;
  double radius = 0, length = 0;
  int segments = 0;
};
// Where an outlet is closed by a plate, it opens at `opens_at` (never when absent).
struct Outlet {
  bool closed = false;
  std::optional<double> opens_at;  // s
};
// A conical frustum: the outlet circle (bottom_radius) at `base`, the top circle height above.
struct HopperWall {
  Vec3d base, axis;
  double top_radius = 0, bottom_radius = 0, height = 0;
  Outlet outlet;
  int segments = 0;
};
// A cylindrical bin of `radius` and `height` on a conical hopper of `cone_height` (0: a flat
// bottom) whose outlet circle of `outlet_radius` is centred at `base`.
struct SiloWall {
  Vec3d base, axis;
  double radius = 0, height = 0, cone_height = 0, outlet_radius = 0;
  Outlet outlet;
  int segments = 0;
};

enum class WallKind { mesh, plane, box, cylinder, drum, hopper, silo };

struct WallSpec {
  std::string name;  // unique; "<kind>_<index in walls>" when not given
  WallKind kind = WallKind::plane;
  int material = -1;
  std::variant<MeshWall, PlaneWall, BoxWall, CylinderWall, DrumWall, HopperWall, SiloWall> shape;
  WallMotion motion;
  SourceRef source;
};

// volume: the default volume law, the paper's Eqs. 12-13 made linear in the overlap volume where
// that is softer (bounded stiffness; docs/contact.md); volume_paper: Eqs. 12-13 exactly as
// printed (unbounded stiffness for flat contacts, kept for comparison); linear: BLAZE-DEM.
enum class ContactModel { volume, volume_paper, linear };
// Whether the model computes overlap volumes (the volume laws) rather than depths (linear).
inline bool is_volume_model(ContactModel model) {
  return model != ContactModel::linear;
}

// BLAZE-DEM Eqs. 2-3: F_N = K_N delta n - eta v, F_T = -min(mu K_N delta, gamma |v_T|) t.
struct LinearContactParameters {
  double stiffness = 0;           // K_N, N/m
  double damping = 0;             // eta, N s/m
  double tangential_damping = 0;  // gamma, N s/m (with friction)
};

// The physics a scene calls for; anything absent is not simulated (docs/design.md, "Simulate
// only the effects a scene calls for").
struct Effects {
  std::optional<Vec3d> gravity;  // m/s^2
  std::optional<ContactModel> contact;
  LinearContactParameters linear;  // when contact is linear
  bool friction = false;
  bool rotation = false;
  std::optional<double> drag_alpha;  // quadratic drag F = -alpha |v| v, kg/m (BLAZE-DEM §5.1)
  // Implied by other sections:
  bool walls = false;         // the wall list is not empty
  bool moving_walls = false;  // some wall moves
  bool feed = false;          // some feed inserts particles during the run
};

enum class VtkParticles { surfaces, points };
enum class Probe { kinetic_energy, wall_forces, contact_count, bed_height, energy };

// The file format of trajectory frames (solver/io/trajectory.hpp): CSV text with 17 digits, or
// HDF5 (one file a frame, one compound dataset; docs/scenes.md, "Output files").
enum class TrajectoryFormat { csv, hdf5 };
// Runs of at least this many particles (at the start and from every feed) write HDF5 frames
// unless the scene names the format: a CSV frame of 1e6 particles is about 0.35 GB.
constexpr std::size_t kHdf5TrajectoryParticles = 10000;
struct TrajectoryOutput {
  long long every = 0;    // steps
  std::string directory;  // as written (relative: to the working directory of the run)
  std::optional<TrajectoryFormat> format;  // not given: by the run's size (above)
};
// ParaView files (solver/io/vtk_output.hpp): particles as their posed polyhedral surfaces or as
// points with orientation, the walls where they are, and a .pvd time series of each.
struct VtkOutput {
  long long every = 0;    // steps
  std::string directory;  // as written
  // Not given: surfaces for runs of at most kVtkSurfaceParticleLimit particles, else points
  // (vtk_particles_for).
  std::optional<VtkParticles> particles;
};
struct ProbeOutput {
  long long every = 0;  // steps
  std::string file;     // CSV, as written
  std::vector<Probe> quantities;
};
// Checkpoints of the production solver (solver/io/checkpoint.hpp), from which `talus run
// --resume DIRECTORY` continues the run exactly.
struct CheckpointOutput {
  long long every = 0;    // steps
  std::string directory;  // as written
  int keep = 2;           // the newest files kept; older ones are removed
};
struct Outputs {
  std::optional<TrajectoryOutput> trajectories;
  std::optional<ProbeOutput> probes;
  std::optional<VtkOutput> vtk;
  std::optional<CheckpointOutput> checkpoint;
};

enum class Backend { automatic, cpu, cuda };
enum class Precision { float32, float64 };

// Scene::made_particles: a list of initial particles waiting to be taken (`full`), or none.
struct MadeParticles {
  bool full = false;
  std::vector<ParticleState> list;
};

struct Scene {
  std::string file;             // the scene file as given to load_scene
  std::string directory;        // relative mesh paths resolve against it
  double time_step = 0;         // s (resolved from the time-step advisor when `step: auto`)
  bool time_step_auto = false;  // the scene wrote `time: {step: auto}`
  SourceRef time_step_source;   // where time.step was written (the advisor's errors name it)
  SourceRef contact_source;     // where effects.contact was written (the step's refusals name it)
  double end_time = 0;          // s
  std::uint64_t seed = 0;
  Backend backend = Backend::automatic;
  Precision precision = Precision::float64;
  // Verlet skin of the pair list, m: both backends keep their candidate pairs (bounding spheres
  // within r_a + r_b + skin; the GPU's with slots of contact history) until some particle has
  // moved 0.45 skin since the build or the particles change (0: every step). Not given: a tenth of
  // the largest bounding diameter. The results do not depend on it; only the work per step does.
  std::optional<double> skin;
  // The GPU backend sums each particle's forces in pair order, so a run does not depend on thread
  // scheduling (the default); false: by atomic additions (faster, not bit-reproducible). The
  // host backend is deterministic either way.
  bool deterministic = true;
  // The simulated region (`domain: {min, max}`; docs/scenes.md): a particle whose centroid leaves
  // it is removed at the end of the step, taking its energy to the ledger's `removed`. Not given:
  // all of space. Every initial particle and feed region lies inside it (the loader checks).
  std::optional<Box> domain;
  SourceRef domain_source;
  // Particles renumbered in the order of their grid cells (a Z-order curve) at every build of the
  // pair list (`reorder`): neighbours then sit near each other in memory. The physics is
  // the same; on the CUDA backend the sums' order, and so the last bits, are not (the host sums
  // each particle's contacts in its partners' id order, whatever the order in memory). Not given:
  // on the CUDA backend (6 % off the 1e6 bed's step, 23 % when its particles are numbered at
  // random), off on the host, which gained nothing at 27,000 particles when it renumbered at every
  // step (benchmarks/README.md).
  std::optional<bool> reorder;
  // A run on several ranks (docs/parallel.md): where the most particles a rank holds exceed the
  // mean over the ranks by this ratio at a rebuild of the pair list, the boxes are cut again from
  // every particle (`decomposition: {rebalance: R}`). One process ignores it.
  double rebalance = 1.25;
  std::vector<Material> materials;
  std::vector<MaterialPair> material_pairs;
  std::vector<ParticleTemplate> templates;
  std::vector<ParticleState> particles;  // the explicit list
  std::vector<LatticeRequest> lattices;
  std::vector<RandomFillRequest> random_fills;
  // How many initial particles the three above would make but were taken out
  // (without_initial_particles, initial_particles.hpp): a resumed run's step is built without
  // them, and its checkpoint's count is checked against this many (step_state.hpp). 0 otherwise.
  std::size_t left_out_particles = 0;
  // The initial particles once made from the lists above, handed on (initial_particles.hpp,
  // keep_initial_particles): `talus run` makes them to check them, and the solver it builds next
  // takes them instead of placing a random fill a second time. Copies of the scene share it; the
  // first initial_particles() call takes the list, a later one makes it again.
  std::shared_ptr<MadeParticles> made_particles = std::make_shared<MadeParticles>();
  std::vector<FeedRequest> feeds;
  std::vector<WallSpec> walls;
  Effects effects;
  Outputs outputs;

  // Index by name, -1 when absent.
  int material_index(const std::string& name) const;
  int template_index(const std::string& name) const;
  // Friction and restitution between two materials: the pair's override if the scene gives
  // one, else the material's own value for a like pair, else the mean of the two materials'.
  double pair_friction(int material_a, int material_b) const;
  double pair_restitution(int material_a, int material_b) const;
};

// Names as written in scene files.
const char* to_string(WallKind kind);
const char* to_string(ContactModel model);
const char* to_string(Probe probe);
const char* to_string(Backend backend);
const char* to_string(Precision precision);
const char* to_string(VtkParticles particles);

}  // namespace talus
