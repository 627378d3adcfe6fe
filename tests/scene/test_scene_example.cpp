// The complete example scene of docs/scenes.md and the example of each wall kind: they load, hold
// the values written in them, and are the very text the documentation shows.
#include <algorithm>
#include <cmath>
#include <regex>
#include <variant>

#include "tests/scene/scene_test_util.hpp"

namespace talus {
namespace {

// Values are parsed from decimal text by strtod (correctly rounded) and, where the loader
// computes something (a normalised axis, a quaternion from an angle), by a few operations:
// a few ulps of 1.
constexpr double kRoundOff = 1e-14;

void expect_vec(const Vec3d& actual, const Vec3d& expected, double tolerance = kRoundOff) {
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(actual[k], expected[k], tolerance) << "component " << k;
}

TEST(SceneExample, LoadsWithEveryValueAsWritten) {
  const Scene scene = load_scene(scene_data_dir() + "/example.yaml");
  EXPECT_EQ(scene.time_step, 2.0e-6);
  EXPECT_EQ(scene.end_time, 0.5);
  EXPECT_EQ(scene.seed, 2024u);
  EXPECT_EQ(scene.backend, Backend::automatic);
  EXPECT_EQ(scene.precision, Precision::float64);

  ASSERT_EQ(scene.materials.size(), 2u);
  const int glass = scene.material_index("glass"), steel = scene.material_index("steel");
  ASSERT_EQ(glass, 0);
  ASSERT_EQ(steel, 1);
  EXPECT_EQ(scene.materials[glass].density, 2500);
  EXPECT_EQ(scene.materials[glass].youngs_modulus, 6.0e7);
  EXPECT_EQ(scene.materials[glass].poisson_ratio, 0.23);
  EXPECT_EQ(scene.materials[steel].friction, 0.3);
  EXPECT_EQ(scene.materials[steel].restitution, 0.9);
  EXPECT_EQ(scene.materials[steel].source.line, 18);  // the first key under `steel:`
  // The pair override, in either order; like pairs keep the material's own values.
  EXPECT_EQ(scene.pair_friction(glass, steel), 0.25);
  EXPECT_EQ(scene.pair_friction(steel, glass), 0.25);
  EXPECT_EQ(scene.pair_restitution(steel, glass), 0.7);
  EXPECT_EQ(scene.pair_friction(glass, glass), 0.4);
  EXPECT_EQ(scene.pair_restitution(steel, steel), 0.9);

  ASSERT_EQ(scene.templates.size(), 3u);
  const ParticleTemplate& grain = scene.templates[scene.template_index("grain")];
  EXPECT_EQ(grain.kind, ParticleShapeKind::polyhedron);
  EXPECT_EQ(grain.resolved_spec, "dodecahedron:0.01");
  EXPECT_TRUE(grain.mesh_file.empty());
  EXPECT_EQ(grain.shape.faces.size(), 12u);
  EXPECT_NEAR(grain.bounding_radius, 0.005, 0.005 * kRoundOff);  // D is the circumscribed diameter
  EXPECT_EQ(grain.material, glass);
  const ParticleTemplate& pebble = scene.templates[scene.template_index("pebble")];
  EXPECT_EQ(pebble.mesh_file, scene_data_dir() + "/meshes/tetra.obj");
  EXPECT_EQ(pebble.mesh_scale, 0.001);
  EXPECT_EQ(pebble.shape.faces.size(), 4u);
  // Alternate corners of a 6 mm cube: a third of 216 mm^3; exact up to the hull's round-off.
  EXPECT_NEAR(pebble.volume, 72e-9, 72e-9 * 1e-12);
  EXPECT_NEAR(pebble.bounding_radius, 3e-3 * std::sqrt(3.0), 1e-15);
  const ParticleTemplate& ball = scene.templates[scene.template_index("ball")];
  EXPECT_EQ(ball.kind, ParticleShapeKind::sphere);
  EXPECT_EQ(ball.sphere_radius, 0.004);
  EXPECT_NEAR(ball.volume, 4.0 / 3.0 * M_PI * 64e-9, 64e-9 * kRoundOff);
  EXPECT_EQ(ball.material, steel);

  ASSERT_EQ(scene.particles.size(), 2u);
  const ParticleState& first = scene.particles[0];
  EXPECT_EQ(first.template_index, scene.template_index("grain"));
  expect_vec(first.position, {0, 0, 0.05});
  // 30 degrees about z: (cos 15°, 0, 0, sin 15°).
  EXPECT_NEAR(first.orientation.w, std::cos(M_PI / 12), kRoundOff);
  EXPECT_NEAR(first.orientation.z, std::sin(M_PI / 12), kRoundOff);
  EXPECT_EQ(first.orientation.x, 0);
  expect_vec(first.velocity, {0, 0, -1});
  expect_vec(first.angular_velocity, {0, 0, 10});
  EXPECT_EQ(first.source.key, "particles[0].explicit[0]");
  EXPECT_EQ(scene.particles[1].orientation.w, 1);

  ASSERT_EQ(scene.lattices.size(), 1u);
  const LatticeRequest& lattice = scene.lattices[0];
  expect_vec(lattice.region.box_min, {-0.05, -0.05, 0});
  expect_vec(lattice.region.box_max, {0.05, 0.05, 0.03});
  expect_vec(lattice.spacing, {0.012, 0.012, 0.012});
  EXPECT_TRUE(lattice.random_orientation);
  EXPECT_EQ(lattice.seed, 2024u + 1 + 1);  // the scene's seed + place in the list + 1

  ASSERT_EQ(scene.random_fills.size(), 1u);
  const RandomFillRequest& fill = scene.random_fills[0];
  EXPECT_EQ(fill.region.kind, RegionKind::cylinder);
  EXPECT_EQ(fill.region.radius, 0.04);
  EXPECT_EQ(fill.region.height, 0.03);
  EXPECT_NEAR(fill.region.volume(), M_PI * 0.04 * 0.04 * 0.03, 1e-18);
  EXPECT_EQ(fill.count, 50);
  EXPECT_EQ(fill.volume_fraction, 0);
  EXPECT_EQ(fill.seed, 7u);
  EXPECT_TRUE(fill.random_orientation);

  ASSERT_EQ(scene.feeds.size(), 1u);
  const FeedRequest& feed = scene.feeds[0];
  EXPECT_EQ(feed.template_index, scene.template_index("ball"));
  EXPECT_EQ(feed.rate, 400);
  EXPECT_EQ(feed.start, 0.1);
  EXPECT_EQ(feed.stop, 0.3);
  expect_vec(feed.velocity, {0, 0, -0.5});
  EXPECT_EQ(feed.seed, 2024u + 3 + 1);

  ASSERT_EQ(scene.walls.size(), 2u);
  const WallSpec& drum = scene.walls[0];
  EXPECT_EQ(drum.name, "drum");
  EXPECT_EQ(drum.kind, WallKind::drum);
  EXPECT_EQ(drum.material, steel);
  const DrumWall& drum_shape = std::get<DrumWall>(drum.shape);
  expect_vec(drum_shape.center, {0, 0, 0.05});
  expect_vec(drum_shape.axis, {1, 0, 0});
  EXPECT_EQ(drum_shape.radius, 0.1);
  EXPECT_EQ(drum_shape.length, 0.12);
  EXPECT_EQ(drum_shape.segments, 96);
  EXPECT_EQ(drum.motion.kind, WallMotion::Kind::rotation);
  EXPECT_NEAR(drum.motion.angular_speed(), M_PI, kRoundOff);  // 30 rpm = pi rad/s
  const WallSpec& baffle = scene.walls[1];
  EXPECT_EQ(baffle.name, "baffle");
  const MeshWall& plate = std::get<MeshWall>(baffle.shape);
  EXPECT_EQ(plate.file, scene_data_dir() + "/meshes/plate.obj");
  EXPECT_EQ(plate.mesh.triangles.size(), 2u);
  EXPECT_EQ(plate.scale, 0.05);
  EXPECT_NEAR(plate.rotation.w, std::cos(M_PI / 4), kRoundOff);
  EXPECT_NEAR(plate.rotation.y, std::sin(M_PI / 4), kRoundOff);
  expect_vec(plate.translation, {0, 0, -0.04});

  const Effects& effects = scene.effects;
  ASSERT_TRUE(effects.gravity.has_value());
  expect_vec(*effects.gravity, {0, 0, -9.81});
  EXPECT_EQ(effects.contact, ContactModel::volume);
  EXPECT_TRUE(effects.friction);
  EXPECT_TRUE(effects.rotation);
  EXPECT_EQ(effects.drag_alpha, 1.0e-4);
  EXPECT_TRUE(effects.walls);
  EXPECT_TRUE(effects.moving_walls);
  EXPECT_TRUE(effects.feed);

  ASSERT_TRUE(scene.outputs.trajectories.has_value());
  EXPECT_EQ(scene.outputs.trajectories->every, 1000);
  EXPECT_EQ(scene.outputs.trajectories->directory, "out/trajectory");
  ASSERT_TRUE(scene.outputs.vtk.has_value());
  EXPECT_EQ(scene.outputs.vtk->every, 5000);
  EXPECT_EQ(scene.outputs.vtk->directory, "out/paraview");
  EXPECT_EQ(scene.outputs.vtk->particles, VtkParticles::surfaces);
  ASSERT_TRUE(scene.outputs.probes.has_value());
  EXPECT_EQ(scene.outputs.probes->every, 100);
  EXPECT_EQ(scene.outputs.probes->file, "out/probes.csv");
  const std::vector<Probe> probes = {Probe::kinetic_energy, Probe::wall_forces,
                                     Probe::contact_count, Probe::bed_height};
  EXPECT_EQ(scene.outputs.probes->quantities, probes);
}

// A wall example appended to the scene of walls/preamble.yaml.
Scene load_wall_example(const std::string& kind) {
  const std::string dir = scene_data_dir() + "/walls";
  return parse_scene(
      read_text_file(dir + "/preamble.yaml") + read_text_file(dir + "/" + kind + ".yaml"),
      kind + ".yaml", dir);
}

// A plane shaken up and down (the tapped beds of experiments/platonic_packing): the direction
// normalised, the amplitude, frequency, start and cycles as given; a moving wall.
TEST(SceneExample, AnOscillatingWallLoadsWithItsValues) {
  const std::string dir = scene_data_dir() + "/walls";
  const Scene scene = parse_scene(read_text_file(dir + "/preamble.yaml") + R"(walls:
  - plane:
      point: [0, 0, 0]
      normal: [0, 0, 1]
      size: 0.5
      material: steel
      motion:
        oscillation: {direction: [0, 0, 2], amplitude: 0.0015, frequency: 30, start: 0.4,
                      cycles: 5}
)",
                                  "tray.yaml", dir);
  const WallMotion& m = scene.walls.at(0).motion;
  EXPECT_EQ(m.kind, WallMotion::Kind::oscillation);
  expect_vec(m.direction, {0, 0, 1});
  EXPECT_EQ(m.amplitude, 0.0015);
  EXPECT_EQ(m.frequency, 30);
  EXPECT_EQ(m.start, 0.4);
  EXPECT_EQ(m.cycles, 5);
  EXPECT_TRUE(scene.effects.moving_walls);
}

TEST(SceneExample, EachWallKindLoadsWithItsValues) {
  {
    const Scene scene = load_wall_example("plane");
    ASSERT_EQ(scene.walls.size(), 1u);
    EXPECT_EQ(scene.walls[0].name, "plane_0");
    const PlaneWall& plane = std::get<PlaneWall>(scene.walls[0].shape);
    expect_vec(plane.normal, {0, 0, 1});
    EXPECT_EQ(plane.size, 0.5);
    EXPECT_FALSE(scene.effects.moving_walls);
  }
  {
    const Scene scene = load_wall_example("box");
    const BoxWall& box = std::get<BoxWall>(scene.walls.at(0).shape);
    expect_vec(box.max, {0.05, 0.05, 0.2});
    EXPECT_TRUE(box.open_top);
    EXPECT_EQ(scene.walls[0].motion.kind, WallMotion::Kind::translation);
    expect_vec(scene.walls[0].motion.velocity, {0.01, 0, 0});
    EXPECT_TRUE(scene.effects.moving_walls);
  }
  {
    const Scene scene = load_wall_example("cylinder");
    const CylinderWall& cylinder = std::get<CylinderWall>(scene.walls.at(0).shape);
    EXPECT_EQ(cylinder.radius, 0.05);
    EXPECT_EQ(cylinder.height, 0.2);
    EXPECT_TRUE(cylinder.bottom_cap);
    EXPECT_FALSE(cylinder.top_cap);
    EXPECT_EQ(cylinder.segments, 48);
  }
  {
    const Scene scene = load_wall_example("drum");
    const DrumWall& drum = std::get<DrumWall>(scene.walls.at(0).shape);
    expect_vec(drum.axis, {0, 1, 0});
    EXPECT_EQ(drum.segments, 64);                                              // the default
    EXPECT_NEAR(scene.walls[0].motion.angular_speed(), -M_PI / 2, kRoundOff);  // -15 rpm
  }
  {
    const Scene scene = load_wall_example("hopper");
    EXPECT_EQ(scene.walls.at(0).name, "funnel");
    const HopperWall& hopper = std::get<HopperWall>(scene.walls[0].shape);
    EXPECT_EQ(hopper.bottom_radius, 0.01);
    EXPECT_EQ(hopper.top_radius, 0.06);
    EXPECT_EQ(hopper.height, 0.1);
    EXPECT_TRUE(hopper.outlet.closed);
    EXPECT_EQ(hopper.outlet.opens_at, 0.25);
  }
  {
    const Scene scene = load_wall_example("silo");
    const SiloWall& silo = std::get<SiloWall>(scene.walls.at(0).shape);
    expect_vec(silo.axis, {0, 0, 1});  // the default
    EXPECT_EQ(silo.cone_height, 0.04);
    EXPECT_EQ(silo.outlet_radius, 0.012);
    EXPECT_FALSE(silo.outlet.closed);
    EXPECT_FALSE(silo.outlet.opens_at.has_value());
  }
  {
    const Scene scene = load_wall_example("mesh");
    const MeshWall& mesh = std::get<MeshWall>(scene.walls.at(0).shape);
    EXPECT_EQ(mesh.file, scene_data_dir() + "/meshes/plate.obj");  // via ../
    EXPECT_EQ(mesh.mesh.vertices.size(), 4u);
    EXPECT_EQ(mesh.scale, 0.4);
    EXPECT_EQ(scene.effects.contact, ContactModel::linear);
    EXPECT_EQ(scene.effects.linear.stiffness, 1.0e4);
    EXPECT_EQ(scene.effects.linear.tangential_damping, 0.5);
  }
}

// docs/scenes.md shows each test input after a marker "<!-- test input: PATH -->": the block
// must be the file, byte for byte, and every example file must be shown.
TEST(SceneExample, DocumentationShowsTheTestInputsVerbatim) {
  const std::string docs = read_text_file(std::string(TALUS_SOURCE_DIR) + "/docs/scenes.md");
  const std::regex block(R"(<!-- test input: ([^ ]+) -->\n```yaml\n([\s\S]*?)```)");
  std::vector<std::string> shown;
  for (auto it = std::sregex_iterator(docs.begin(), docs.end(), block);
       it != std::sregex_iterator(); ++it) {
    const std::string path = (*it)[1];
    SCOPED_TRACE(path);
    EXPECT_EQ((*it)[2].str(), read_text_file(std::string(TALUS_SOURCE_DIR) + "/" + path));
    shown.push_back(path);
  }
  std::vector<std::string> expected = {"tests/scene/data/example.yaml"};
  for (const char* kind : {"plane", "box", "cylinder", "drum", "hopper", "silo", "mesh"})
    expected.push_back(std::string("tests/scene/data/walls/") + kind + ".yaml");
  for (const std::string& path : expected)
    EXPECT_TRUE(std::count(shown.begin(), shown.end(), path) == 1) << path << " not shown once";
}

}  // namespace
}  // namespace talus
