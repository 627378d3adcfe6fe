// What the loader fills in: defaults for keys left out, values it derives (counts from volume
// fractions, seeds, pair properties, resolved paths), and the accepted spellings of values.
#include <cmath>

#include "tests/scene/scene_test_util.hpp"

namespace talus {
namespace {

Scene with(const std::vector<std::pair<std::string, std::string>>& edits) {
  std::string text = kValidScene;
  for (const auto& [from, to] : edits) text = replaced(text, from, to);
  return parse_scene(text, "values.yaml", scene_data_dir());
}

const std::string kOneParticle = "  - explicit:\n      - {template: grain, position: [0, 0, 0.05]}";

TEST(SceneValues, DefaultsOfKeysLeftOut) {
  const Scene scene = with({});
  EXPECT_EQ(scene.file, "values.yaml");
  EXPECT_EQ(scene.seed, 3u);
  EXPECT_EQ(scene.backend, Backend::automatic);
  EXPECT_EQ(scene.precision, Precision::float64);
  EXPECT_FALSE(scene.skin.has_value());
  EXPECT_TRUE(scene.deterministic);
  EXPECT_TRUE(scene.material_pairs.empty());
  const ParticleState& particle = scene.particles.at(0);
  EXPECT_EQ(particle.orientation.w, 1);
  EXPECT_EQ(norm(particle.velocity), 0);
  EXPECT_EQ(norm(particle.angular_velocity), 0);
  EXPECT_FALSE(scene.effects.rotation);
  EXPECT_FALSE(scene.effects.drag_alpha.has_value());
  EXPECT_FALSE(scene.effects.walls);
  EXPECT_FALSE(scene.effects.feed);
  EXPECT_FALSE(scene.outputs.trajectories.has_value());
  EXPECT_FALSE(scene.outputs.probes.has_value());
  EXPECT_FALSE(scene.outputs.vtk.has_value());
  // `effects:` with nothing under it: no physics at all.
  const Scene bare =
      with({{"effects:\n  gravity: [0, 0, -9.81]\n  contact: volume\n  friction: "
             "true\n",
             "effects:\n"}});
  EXPECT_FALSE(bare.effects.gravity.has_value());
  EXPECT_FALSE(bare.effects.contact.has_value());
  EXPECT_FALSE(bare.effects.friction);
}

TEST(SceneValues, ChoicesAndSpellings) {
  const Scene scene = with({{"seed: 3",
                             "seed: 3\nbackend: cuda\nprecision: float\nskin: 2.5e-4\n"
                             "deterministic: false"},
                            {"friction: true", "friction: off\n  rotation: yes"},
                            {"contact: volume",
                             "contact: {model: linear, stiffness: 2.5e3, "
                             "damping: 0.25}"}});
  EXPECT_EQ(scene.backend, Backend::cuda);
  EXPECT_EQ(scene.precision, Precision::float32);
  EXPECT_EQ(scene.skin, 2.5e-4);
  EXPECT_FALSE(scene.deterministic);
  EXPECT_FALSE(scene.effects.friction);
  EXPECT_TRUE(scene.effects.rotation);
  EXPECT_EQ(scene.effects.contact, ContactModel::linear);
  EXPECT_EQ(scene.effects.linear.stiffness, 2.5e3);
  EXPECT_EQ(scene.effects.linear.damping, 0.25);
  EXPECT_EQ(scene.effects.linear.tangential_damping, 0);  // not needed without friction
}

TEST(SceneValues, VolumeFractionBecomesACount) {
  // Spheres of radius 5 mm (5.236e-7 m^3) at 0.1 of a litre: 1e-4 / 5.236e-7 = 190.99 -> 191.
  const Scene scene = with(
      {{"    material: glass\n", "    material: glass\n  ball: {sphere: 0.005, material: glass}\n"},
       {kOneParticle,
        "  - random:\n      template: ball\n      region: {box: {min: [0, 0, 0], "
        "max: [0.1, 0.1, 0.1]}}\n      volume_fraction: 0.1\n      "
        "random_orientation: false"}});
  const RandomFillRequest& fill = scene.random_fills.at(0);
  EXPECT_EQ(fill.count, 191);
  EXPECT_EQ(fill.volume_fraction, 0.1);
  EXPECT_FALSE(fill.random_orientation);
  EXPECT_EQ(fill.seed, 3u + 0 + 1);  // the scene's seed + place in the list + 1
  EXPECT_EQ(fill.source.key, "particles[0].random");
  EXPECT_EQ(fill.source.where(), "values.yaml:17:7: particles[0].random");  // under `- random:`
}

TEST(SceneValues, CountsAcceptIntegralExponentNotation) {
  const Scene scene = with({{kOneParticle,
                             "  - random:\n      template: grain\n      region: "
                             "{box: {min: [0, 0, 0], max: [1, 1, 1]}}\n      count: "
                             "1e3"}});
  EXPECT_EQ(scene.random_fills.at(0).count, 1000);
}

TEST(SceneValues, FeedDefaultsRunToTheEnd) {
  const Scene scene = with({{kOneParticle,
                             "  - feed:\n      template: grain\n      region: {box: "
                             "{min: [0, 0, 0], max: [0.1, 0.1, 0.1]}}\n      rate: "
                             "50\n      seed: 11"}});
  const FeedRequest& feed = scene.feeds.at(0);
  EXPECT_EQ(feed.start, 0);
  EXPECT_EQ(feed.stop, 0.1);  // time.end
  EXPECT_EQ(feed.seed, 11u);
  EXPECT_TRUE(feed.random_orientation);
  EXPECT_TRUE(scene.effects.feed);
}

TEST(SceneValues, LatticeSpacingPerAxis) {
  const Scene scene =
      with({{kOneParticle,
             "  - lattice:\n      template: grain\n      region: {box: {min: [0, 0, "
             "0], max: [0.1, 0.1, 0.1]}}\n      spacing: [0.01, 0.02, 0.03]"}});
  // 0.01 equals the bounding diameter of dodecahedron:0.01: touching neighbours are allowed.
  const LatticeRequest& lattice = scene.lattices.at(0);
  EXPECT_EQ(lattice.spacing.x, 0.01);
  EXPECT_EQ(lattice.spacing.z, 0.03);
  EXPECT_FALSE(lattice.random_orientation);
}

TEST(SceneValues, PairPropertiesDefaultToTheMean) {
  const Scene scene =
      with({{"templates:",
             "  steel: {density: 7800, youngs_modulus: 2.0e8, poisson_ratio: 0.3, "
             "friction: 0.3, restitution: 0.6}\nmaterial_pairs:\n  - {materials: [steel, "
             "glass], restitution: 0.5}\ntemplates:"}});
  const int glass = scene.material_index("glass"), steel = scene.material_index("steel");
  // Written as [steel, glass], stored in index order.
  EXPECT_EQ(scene.material_pairs.at(0).material_a, glass);
  EXPECT_EQ(scene.material_pairs.at(0).material_b, steel);
  EXPECT_FALSE(scene.material_pairs.at(0).friction.has_value());
  // No friction override: the mean (0.4 + 0.3) / 2, rounded once.
  EXPECT_DOUBLE_EQ(scene.pair_friction(glass, steel), 0.35);
  EXPECT_EQ(scene.pair_restitution(steel, glass), 0.5);
  EXPECT_EQ(scene.material_index("sand"), -1);
  EXPECT_EQ(scene.template_index("sand"), -1);
}

// A direction is normalised after scaling by its largest component: one of huge (or tiny)
// components is still a direction, not the NaN its overflowing (or vanishing) norm once made.
TEST(SceneValues, DirectionsOfHugeOrTinyComponentsAreNormalised) {
  for (const std::string& normal : {"[1e300, 1e300, 0]", "[1e-300, 1e-300, 0]"}) {
    const Scene scene =
        with({{"effects:", "walls:\n  - plane: {point: [0, 0, 0], normal: " + normal +
                               ", size: 1, material: glass}\neffects:"}});
    const PlaneWall& plane = std::get<PlaneWall>(scene.walls.at(0).shape);
    EXPECT_NEAR(plane.normal.x, std::sqrt(0.5), 1e-15) << normal;
    EXPECT_NEAR(plane.normal.y, std::sqrt(0.5), 1e-15) << normal;
    EXPECT_EQ(plane.normal.z, 0) << normal;
  }
}

TEST(SceneValues, MeshTemplateScaleInTheSpec) {
  // Twice the scale of example.yaml: 8 times its 72 mm^3 volume; hull round-off only.
  const Scene scene = with({{"dodecahedron:0.01", "meshes/tetra.obj:0.002"}});
  const ParticleTemplate& t = scene.templates.at(0);
  EXPECT_EQ(t.mesh_file, scene_data_dir() + "/meshes/tetra.obj");
  EXPECT_EQ(t.resolved_spec, scene_data_dir() + "/meshes/tetra.obj:0.002");
  EXPECT_EQ(t.mesh_scale, 0.002);
  EXPECT_NEAR(t.volume, 576e-9, 576e-9 * 1e-12);
  EXPECT_NEAR(t.bounding_radius, 6e-3 * std::sqrt(3.0), 1e-15);
}

TEST(SceneValues, VtkOutputDefaultsAndParticleForms) {
  const std::string outputs = "  friction: true\noutputs:\n  ";
  const Scene plain = with({{"  friction: true", outputs + "vtk: {every: 20}"}});
  ASSERT_TRUE(plain.outputs.vtk.has_value());
  EXPECT_EQ(plain.outputs.vtk->every, 20);
  EXPECT_EQ(plain.outputs.vtk->directory, "vtk");
  EXPECT_FALSE(plain.outputs.vtk->particles.has_value());  // chosen by the run's particle count
  EXPECT_FALSE(plain.outputs.trajectories.has_value());
  const Scene points =
      with({{"  friction: true", outputs + "vtk: {every: 3, directory: pv, particles: points}"}});
  EXPECT_EQ(points.outputs.vtk->every, 3);
  EXPECT_EQ(points.outputs.vtk->directory, "pv");
  EXPECT_EQ(points.outputs.vtk->particles, VtkParticles::points);
  const Scene surfaces =
      with({{"  friction: true", outputs + "vtk: {every: 1, particles: surfaces}"}});
  EXPECT_EQ(surfaces.outputs.vtk->particles, VtkParticles::surfaces);
}

TEST(SceneValues, CheckpointOutputDefaults) {
  const std::string outputs = "  friction: true\noutputs:\n  ";
  EXPECT_FALSE(with({}).outputs.checkpoint.has_value());
  const Scene plain = with({{"  friction: true", outputs + "checkpoint: {every: 50}"}});
  ASSERT_TRUE(plain.outputs.checkpoint.has_value());
  EXPECT_EQ(plain.outputs.checkpoint->every, 50);
  EXPECT_EQ(plain.outputs.checkpoint->directory, "checkpoints");
  EXPECT_EQ(plain.outputs.checkpoint->keep, 2);
  const Scene given =
      with({{"  friction: true", outputs + "checkpoint: {every: 7, directory: ck, keep: 5}"}});
  EXPECT_EQ(given.outputs.checkpoint->every, 7);
  EXPECT_EQ(given.outputs.checkpoint->directory, "ck");
  EXPECT_EQ(given.outputs.checkpoint->keep, 5);
}

TEST(SceneValues, NamesWrittenForEachKind) {
  EXPECT_STREQ(to_string(WallKind::hopper), "hopper");
  EXPECT_STREQ(to_string(ContactModel::linear), "linear");
  EXPECT_STREQ(to_string(Probe::bed_height), "bed_height");
  EXPECT_STREQ(to_string(Backend::automatic), "auto");
  EXPECT_STREQ(to_string(Precision::float32), "float");
  EXPECT_STREQ(to_string(VtkParticles::surfaces), "surfaces");
  EXPECT_STREQ(to_string(VtkParticles::points), "points");
}

}  // namespace
}  // namespace talus
