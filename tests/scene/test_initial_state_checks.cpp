// Initial states that are not physical (solver/scene/initial_state_checks.hpp): particles through
// each other or through a wall are errors or warnings naming the ids and the scene entries, as are
// particles behind a wall (outside a container, behind a plane or a mesh) and random fills that
// reach outside their container; states that are fine (the example scene, touching particles,
// particles above an open box or below an open outlet) give nothing.
#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "solver/scene/initial_particles.hpp"
#include "solver/scene/initial_state_checks.hpp"
#include "tests/scene/scene_test_util.hpp"

namespace talus {
namespace {

// Spheres of radius 5 mm and cubes of circumscribed diameter 10 mm (sides a = 10 / sqrt(3) mm,
// inscribed radius a / 2 = 2.887 mm), linear contact, no gravity. Particles and walls appended.
const std::string kPreamble = R"(time: {step: 1.0e-5, end: 0.01}
materials:
  steel: {density: 7800, youngs_modulus: 2.0e8, poisson_ratio: 0.3, friction: 0.3, restitution: 0.9}
templates:
  ball: {sphere: 0.005, material: steel}
  cube: {shape: cube:0.01, material: steel}
effects:
  contact: {model: linear, stiffness: 1.0e4, damping: 1.0}
)";

Scene load(const std::string& rest) {
  return parse_scene(kPreamble + rest, "state.yaml", scene_data_dir());
}

std::vector<std::string> warnings_of(const Scene& scene) {
  return check_initial_state(scene, initial_particles(scene));
}

std::vector<std::string> warnings_of(const std::string& rest) {
  return warnings_of(load(rest));
}

// The one warning of the check ("" and a test failure when there is not exactly one).
std::string only_warning(const std::string& rest) {
  const std::vector<std::string> w = warnings_of(rest);
  EXPECT_EQ(w.size(), 1u) << rest;
  return w.size() == 1 ? w[0] : "";
}

// The SceneError of the check (the scene itself loads).
SceneError state_error(const std::string& rest) {
  const Scene scene = load(rest);
  try {
    check_initial_state(scene, initial_particles(scene));
  } catch (const SceneError& e) {
    return e;
  }
  ADD_FAILURE() << "no SceneError for:\n" << rest;
  return SceneError("", 0, 0, "", "<no error>");
}

// Two explicit particles of `shape`, the second at `second` (the first at the origin).
std::string two(const std::string& shape, const std::string& second,
                const std::string& orientation = "[1, 0, 0, 0]") {
  return "particles:\n  - explicit:\n      - {template: " + shape +
         ", position: [0, 0, 0], orientation: " + orientation + "}\n      - {template: " + shape +
         ", position: " + second + "}\n";
}

TEST(InitialState, IdenticalPosesAreAnErrorNamingBothParticlesAndLines) {
  const SceneError e = state_error(two("cube", "[0, 0, 0]"));
  EXPECT_STREQ(e.what(),
               "state.yaml:11:9: particles[0].explicit[0]: particles 0 and 1 (the second of "
               "state.yaml:12:9: particles[0].explicit[1]) start with the centroid of one inside "
               "the other: centres 0 m apart (identical positions), inscribed radii 0.00289 m "
               "and 0.00289 m; the contact law cannot separate such a pair (identical poses feel "
               "no force at all, slightly shifted ones are thrown apart at hundreds of m/s); move "
               "them apart (1 such pair in all)");
  // Shifted by 1 nm: the same error, with the distance.
  EXPECT_NE(state_error(two("cube", "[1.0e-9, 0, 0]")).message().find("centres 1e-09 m apart, "),
            std::string::npos);
}

TEST(InitialState, TheErrorThresholdIsTheCentroidInsideTheOther) {
  // Spheres of radius 5 mm: the centroid of one is inside the other below 5 mm (error), the two
  // overlap below 10 mm (warning), and touch or part at 10 mm and beyond (nothing). 1 um either
  // side of each boundary, far above round-off (1e-18 m) and far below the radii.
  EXPECT_EQ(state_error(two("ball", "[0.004999, 0, 0]")).key(), "particles[0].explicit[0]");
  EXPECT_EQ(only_warning(two("ball", "[0.005001, 0, 0]")),
            "state.yaml:11:9: particles[0].explicit[0]: warning: 1 pair of particles overlaps at "
            "the start with particles of state.yaml:12:9: particles[0].explicit[1]; the contact "
            "law pushes them apart at the first step, turning the overlap's elastic energy into "
            "speed (id pairs: 0-1)");
  EXPECT_EQ(warnings_of(two("ball", "[0.009999, 0, 0]")).size(), 1u);
  EXPECT_TRUE(warnings_of(two("ball", "[0.010001, 0, 0]")).empty());
}

TEST(InitialState, PolyhedraOverlapOnlyWhereTheirBodiesDo) {
  // Face to face, cubes of side 5.774 mm: through each other at 5.0 mm (inscribed spheres meet),
  // apart at 5.9 mm although their bounding spheres (radius 5 mm) overlap.
  EXPECT_EQ(warnings_of(two("cube", "[0.005, 0, 0]")).size(), 1u);
  EXPECT_TRUE(warnings_of(two("cube", "[0.0059, 0, 0]")).empty());
  // The first turned 45 degrees about z reaches a / sqrt(2) = 4.082 mm along x, the second
  // 2.887 mm back from 6.5 mm: 0.47 mm into each other, with the centres 6.52 mm apart (beyond
  // the inscribed spheres' 5.77 mm); a corner of the first (z = 2.887 mm) lies inside the second
  // (raised by 0.5 mm, so that the corner is not on its top face).
  const std::string turned = "{axis: [0, 0, 1], degrees: 45}";
  EXPECT_EQ(warnings_of(two("cube", "[0.0065, 0, 0.0005]", turned)).size(), 1u);
  EXPECT_TRUE(warnings_of(two("cube", "[0.0075, 0, 0.0005]", turned)).empty());
}

TEST(InitialState, OverlapsAreGroupedByEntryWithTheFirstIds) {
  // Two rows of 7 spheres (spacing 10 mm), the second 7 mm beside the first along y: sphere i of
  // one overlaps sphere i of the other (centres 7 mm apart: overlapping, not inside each other),
  // and no other (12.2 mm). Seven pairs, one line, the first five listed.
  const std::string row =
      "  - lattice: {template: ball, region: {box: {min: [0, Y0, 0], max: "
      "[0.07, Y1, 0.01]}}, spacing: 0.01}\n";
  const std::string a = replaced(replaced(row, "Y0", "0"), "Y1", "0.01");
  const std::string b = replaced(replaced(row, "Y0", "0.007"), "Y1", "0.017");
  EXPECT_EQ(only_warning("particles:\n" + a + b),
            "state.yaml:10:14: particles[0].lattice: warning: 7 pairs of particles overlap at "
            "the start with particles of state.yaml:11:14: particles[1].lattice; the contact law "
            "pushes them apart at the first step, turning the overlap's elastic energy into "
            "speed (id pairs: 0-7, 1-8, 2-9, 3-10, 4-11 and 2 more)");
}

TEST(InitialState, AnExplicitParticleOnALatticePointNamesBothEntries) {
  const SceneError e = state_error(
      "particles:\n  - explicit:\n      - {template: ball, position: [0.005, 0.005, 0.005]}\n"
      "  - lattice: {template: ball, region: {box: {min: [0, 0, 0], max: [0.02, 0.01, 0.01]}}, "
      "spacing: 0.01}\n");
  EXPECT_EQ(e.key(), "particles[0].explicit[0]");
  EXPECT_NE(e.message().find("particles 0 and 1 (the second of state.yaml:12:14: "
                             "particles[1].lattice) start with the centroid of one inside the "
                             "other: centres 0 m apart (identical positions)"),
            std::string::npos)
      << e.what();
}

const std::string kBox =
    "walls:\n  - box: {min: [-0.05, -0.05, 0], max: [0.05, 0.05, 0.1], material: steel}\n";

std::string one_ball(const std::string& position) {
  return "particles:\n  - explicit:\n      - {template: ball, position: " + position + "}\n";
}

TEST(InitialState, AParticleThroughAWallFromTheInsideIsAWarning) {
  EXPECT_EQ(only_warning(kBox + one_ball("[0, 0, 0.003]")),
            "state.yaml:13:9: particles[0].explicit[0]: warning: 1 particle crosses wall "
            "'box_0' (state.yaml:10:10: walls[0].box) at the start, its centroid on the "
            "particles' side; the wall pushes it out at the first step (ids: 0)");
  // 5 mm up it touches the floor: nothing. A cube 4 mm up, turned 45 degrees about x, reaches
  // a / sqrt(2) = 4.082 mm down: its lower edge is 0.08 mm through the floor, farther from the
  // centroid than its inscribed radius (2.887 mm); the rays to that edge's corners find it.
  EXPECT_TRUE(warnings_of(kBox + one_ball("[0, 0, 0.005]")).empty());
  EXPECT_EQ(
      warnings_of(kBox + "particles:\n  - explicit:\n      - {template: cube, position: [0, 0, "
                         "0.004], orientation: {axis: [1, 0, 0], degrees: 45}}\n")
          .size(),
      1u);
}

TEST(InitialState, AParticleThroughAWallFromBehindIsAnError) {
  const SceneError e = state_error(kBox + one_ball("[0, 0, -0.003]"));
  EXPECT_STREQ(e.what(),
               "state.yaml:13:9: particles[0].explicit[0]: particle 0 crosses wall 'box_0' "
               "(state.yaml:10:10: walls[0].box) with its centroid 0.003 m behind it, on the side "
               "away from the particles: the wall's contact pushes it along the wall's normal, "
               "through the wall; place it on the particles' side (1 such particle in all)");
}

TEST(InitialState, ParticlesOutsideAClosedContainerAreAWarningOpenOnesAreNot) {
  EXPECT_EQ(only_warning(kBox + one_ball("[0, 0, -0.02]")),
            "state.yaml:13:9: particles[0].explicit[0]: warning: 1 particle lies outside the "
            "closed container 'box_0' (state.yaml:10:10: walls[0].box), which it can never enter "
            "(ids: 0)");
  // Above an open box: it may fall in. Nothing.
  EXPECT_TRUE(warnings_of(replaced(kBox, "material: steel", "open_top: true, material: steel") +
                          one_ball("[0, 0, 0.2]"))
                  .empty());
}

// One wall of `kind` with `keys` (and material steel), as the scene's line 10.
std::string wall(const std::string& kind, const std::string& keys) {
  return "walls:\n  - " + kind + ": {" + keys + ", material: steel}\n";
}

// The warning for the one explicit particle (line 13) behind wall 0, of `kind` at `column`.
std::string behind(const std::string& kind, int column) {
  return fmt::format(
      "state.yaml:13:9: particles[0].explicit[0]: warning: 1 particle lies behind wall "
      "'{0}_0' (state.yaml:10:{1}: walls[0].{0}), on the side away from the particles; it can "
      "reach their side only around the wall's edge, never through it (ids: 0)",
      kind, column);
}

// Whether a ball at `position` gets exactly that warning (true), or nothing (false).
bool behind_wall(const std::string& walls, const std::string& kind, int column,
                 const std::string& position) {
  const std::vector<std::string> w = warnings_of(walls + one_ball(position));
  EXPECT_LE(w.size(), 1u) << position;
  if (w.size() == 1) EXPECT_EQ(w[0], behind(kind, column)) << position;
  return !w.empty();
}

TEST(InitialState, AParticleBehindAPlaneWithinItsSquareIsAWarning) {
  const std::string plane = wall("plane", "point: [0, 0, 0], normal: [0, 0, 1], size: 0.1");
  EXPECT_TRUE(behind_wall(plane, "plane", 12, "[0.01, 0.02, -0.03]"));
  EXPECT_FALSE(behind_wall(plane, "plane", 12, "[0.01, 0.02, 0.03]"));   // in front
  EXPECT_FALSE(behind_wall(plane, "plane", 12, "[0.08, 0.02, -0.03]"));  // beside the square
  // A tilted plane: the side is the normal's.
  const std::string tilted = wall("plane", "point: [0, 0, 0], normal: [1, 0, 1], size: 0.1");
  EXPECT_TRUE(behind_wall(tilted, "plane", 12, "[-0.02, 0, -0.02]"));
  EXPECT_FALSE(behind_wall(tilted, "plane", 12, "[0.02, 0, 0.02]"));
}

TEST(InitialState, AnOpenBoxWarnsBesideAndBeneathItsWallsNotAboveTheRim) {
  const std::string open = replaced(kBox, "material: steel", "open_top: true, material: steel");
  EXPECT_TRUE(behind_wall(open, "box", 10, "[0.08, 0, 0.05]"));    // beside, below the rim
  EXPECT_TRUE(behind_wall(open, "box", 10, "[0, 0.01, -0.02]"));   // beneath the floor
  EXPECT_FALSE(behind_wall(open, "box", 10, "[0, 0, 0.05]"));      // inside
  EXPECT_FALSE(behind_wall(open, "box", 10, "[0.08, 0, 0.2]"));    // above the rim: may fall in
  EXPECT_FALSE(behind_wall(open, "box", 10, "[0.08, 0, -0.02]"));  // beside and beneath: undecided
}

TEST(InitialState, AnOpenCylinderWarnsBesideItsSideAndBeyondItsCaps) {
  const std::string keys = "base: [0, 0, 0], radius: 0.05, height: 0.1";
  const std::string open = wall("cylinder", keys);
  EXPECT_TRUE(behind_wall(open, "cylinder", 15, "[0.08, 0, 0.05]"));
  EXPECT_FALSE(behind_wall(open, "cylinder", 15, "[0.03, 0.02, 0.05]"));  // inside
  EXPECT_FALSE(behind_wall(open, "cylinder", 15, "[0, 0, -0.05]"));       // beyond the open ends
  EXPECT_FALSE(behind_wall(open, "cylinder", 15, "[0, 0, 0.2]"));
  const std::string bottom = wall("cylinder", keys + ", bottom_cap: true");
  EXPECT_TRUE(behind_wall(bottom, "cylinder", 15, "[0, 0.01, -0.05]"));  // beneath the cap
  EXPECT_FALSE(behind_wall(bottom, "cylinder", 15, "[0, 0.01, 0.2]"));   // beyond the open top
  const std::string top = wall("cylinder", keys + ", top_cap: true");
  EXPECT_TRUE(behind_wall(top, "cylinder", 15, "[0, 0.01, 0.2]"));
  EXPECT_FALSE(behind_wall(top, "cylinder", 15, "[0, 0.01, -0.05]"));
  // Along x: beside is off the x axis.
  const std::string along_x = wall("cylinder",
                                   "base: [0, 0, 0], axis: [1, 0, 0], radius: 0.05, "
                                   "height: 0.1");
  EXPECT_TRUE(behind_wall(along_x, "cylinder", 15, "[0.05, 0, 0.08]"));
  EXPECT_FALSE(behind_wall(along_x, "cylinder", 15, "[0.05, 0, 0.03]"));
  // Both caps: a closed container, outside anywhere.
  EXPECT_EQ(only_warning(wall("cylinder", keys + ", bottom_cap: true, top_cap: true") +
                         one_ball("[0.08, 0, -0.05]")),
            "state.yaml:13:9: particles[0].explicit[0]: warning: 1 particle lies outside the "
            "closed container 'cylinder_0' (state.yaml:10:15: walls[0].cylinder), which it can "
            "never enter (ids: 0)");
}

TEST(InitialState, ADrumIsAClosedContainerAboutItsAxis) {
  const std::string drum =
      wall("drum", "center: [0, 0, 0], axis: [0, 1, 0], radius: 0.05, length: 0.1");
  const std::string outside = "closed container 'drum_0'";
  EXPECT_NE(only_warning(drum + one_ball("[0, 0.08, 0]")).find(outside), std::string::npos);
  EXPECT_NE(only_warning(drum + one_ball("[0.08, 0, 0]")).find(outside), std::string::npos);
  EXPECT_TRUE(warnings_of(drum + one_ball("[0.02, 0.04, 0.02]")).empty());
}

TEST(InitialState, AHopperWarnsBesideItsConeAndBeneathAClosedOutlet) {
  // The cone's radius is 0.01 m at z = 0, 0.05 m at z = 0.1: 0.03 m at z = 0.05.
  const std::string keys = "base: [0, 0, 0], bottom_radius: 0.01, top_radius: 0.05, height: 0.1";
  const std::string open = wall("hopper", keys);
  EXPECT_TRUE(behind_wall(open, "hopper", 13, "[0.05, 0, 0.05]"));   // 1.9 cm behind the cone
  EXPECT_TRUE(behind_wall(open, "hopper", 13, "[0, 0.2, 0.09]"));    // far beside it
  EXPECT_FALSE(behind_wall(open, "hopper", 13, "[0.02, 0, 0.05]"));  // inside
  EXPECT_FALSE(behind_wall(open, "hopper", 13, "[0, 0, -0.05]"));    // below the open outlet
  EXPECT_FALSE(behind_wall(open, "hopper", 13, "[0.08, 0, 0.15]"));  // above the open top
  const std::string closed = wall("hopper", keys + ", outlet: closed");
  EXPECT_TRUE(behind_wall(closed, "hopper", 13, "[0, 0, -0.05]"));      // beneath the plate
  EXPECT_FALSE(behind_wall(closed, "hopper", 13, "[0.03, 0, -0.05]"));  // not beneath it
}

TEST(InitialState, ASiloWarnsBesideItsBinAndConeAndBeneathAFlatBottom) {
  // The cone from the outlet (0.01 m) at z = 0 to the bin (0.05 m) at z = 0.05; the bin to 0.15.
  const std::string keys = "base: [0, 0, 0], radius: 0.05, height: 0.1, outlet_radius: 0.01";
  const std::string coned = wall("silo", keys + ", cone_height: 0.05");
  EXPECT_TRUE(behind_wall(coned, "silo", 11, "[0.08, 0, 0.1]"));   // beside the bin
  EXPECT_TRUE(behind_wall(coned, "silo", 11, "[0.05, 0, 0.01]"));  // 2.5 cm behind the cone
  EXPECT_FALSE(behind_wall(coned, "silo", 11, "[0, 0.03, 0.1]"));  // inside the bin
  EXPECT_FALSE(behind_wall(coned, "silo", 11, "[0, 0, 0.02]"));    // inside the cone
  EXPECT_FALSE(behind_wall(coned, "silo", 11, "[0, 0, -0.05]"));   // below the open outlet
  EXPECT_TRUE(behind_wall(wall("silo", keys + ", cone_height: 0.05, outlet: closed"), "silo", 11,
                          "[0, 0, -0.05]"));
  const std::string flat = wall("silo", keys);
  EXPECT_TRUE(behind_wall(flat, "silo", 11, "[0.03, 0, -0.02]"));  // beneath the flat bottom
  EXPECT_FALSE(behind_wall(flat, "silo", 11, "[0, 0, -0.02]"));    // beneath the orifice
  EXPECT_FALSE(behind_wall(flat, "silo", 11, "[0.03, 0, 0.02]"));  // inside
}

TEST(InitialState, AMeshWallWarnsBehindTheTriangleNearestToTheCentroid) {
  // meshes/plate.obj: a square of 0.1 m facing +z. Behind its face: a warning; beyond its edge (the
  // nearest point is on an edge) or in front: nothing.
  const std::string plate = wall("mesh", "file: meshes/plate.obj, scale: 0.1");
  EXPECT_TRUE(behind_wall(plate, "mesh", 11, "[0.01, 0.02, -0.03]"));
  EXPECT_FALSE(behind_wall(plate, "mesh", 11, "[0.01, 0.02, 0.03]"));
  EXPECT_FALSE(behind_wall(plate, "mesh", 11, "[0.08, 0.02, -0.03]"));
  // meshes/tetra.obj at 0.01 m per unit: a closed tetrahedron with its normals out (particles live
  // outside it), inradius 1.73 cm. Inside it: behind every face; beyond a face: in front of it.
  const std::string tetra = wall("mesh", "file: meshes/tetra.obj, scale: 0.01");
  EXPECT_TRUE(behind_wall(tetra, "mesh", 11, "[0.001, 0.002, -0.001]"));
  EXPECT_FALSE(behind_wall(tetra, "mesh", 11, "[0.023, 0.023, -0.023]"));
}

TEST(InitialState, ARandomFillReachingOutsideItsContainerIsNamedOnTheEntry) {
  // Placement keeps bounding spheres inside the fill's region and off the walls' triangles, so a
  // region across a container's wall puts particles on both sides of it: one warning on the
  // entry, with the count outside.
  const auto check = [](const std::string& walls, const std::string& name, int column,
                        const std::string& region, const auto& is_outside) {
    const Scene scene = load(walls + "particles:\n  - random: {template: ball, region: " + region +
                             ", count: 40, seed: 5}\n");
    const std::vector<ParticleState> particles = initial_particles(scene);
    const long long outside = std::count_if(particles.begin(), particles.end(), is_outside);
    ASSERT_GT(outside, 0) << name;  // some land outside, and some inside
    ASSERT_LT(outside, 40) << name;
    const std::vector<std::string> w = check_initial_state(scene, particles);
    ASSERT_EQ(w.size(), 1u) << name;
    EXPECT_EQ(w[0].substr(0, w[0].find(" (ids: ")),
              fmt::format("state.yaml:12:13: particles[0].random: warning: {} particles of this "
                          "random fill lie outside wall '{}' (state.yaml:10:{}: walls[0].{}), "
                          "which holds the fill's other particles: the fill's region reaches "
                          "beyond the wall; keep it on the particles' side",
                          outside, name + "_0", column, name));
  };
  const std::string across_x = "{box: {min: [0.03, -0.05, 0], max: [0.08, 0.05, 0.1]}}";
  check(kBox, "box", 10, across_x, [](const ParticleState& p) { return p.position.x > 0.05; });
  check(wall("cylinder", "base: [0, 0, 0], radius: 0.05, height: 0.1"), "cylinder", 15, across_x,
        [](const ParticleState& p) { return std::hypot(p.position.x, p.position.y) > 0.05; });
  check(wall("plane", "point: [0, 0, 0], normal: [0, 0, 1], size: 0.2"), "plane", 12,
        "{box: {min: [-0.05, -0.05, -0.03], max: [0.05, 0.05, 0.07]}}",
        [](const ParticleState& p) { return p.position.z < 0; });
  // A fill inside its container: nothing.
  EXPECT_TRUE(warnings_of(kBox + "particles:\n  - random: {template: ball, region: {box: {min: "
                                 "[-0.05, -0.05, 0], max: [0.05, 0.05, 0.1]}}, count: 40}\n")
                  .empty());
}

TEST(InitialState, TouchingNeighboursOfALatticeAreNotOverlaps) {
  // Spacing = diameter: neighbours touch, their centre distances within round-off (1e-18 m) of
  // 10 mm, some of them below it; the check's tolerance (1e-8 of the radius) takes them as
  // touching. Spheres and cubes alike (a cube's bounding diameter is its space diagonal, so
  // cubes at that spacing stand apart).
  for (const std::string shape : {"ball", "cube"})
    EXPECT_TRUE(warnings_of("particles:\n  - lattice: {template: " + shape +
                            ", region: {box: {min: [0, 0, 0], max: [0.05, 0.05, 0.05]}}, "
                            "spacing: 0.01}\n")
                    .empty())
        << shape;
}

TEST(InitialState, TheExampleSceneAndTheBuiltInSceneAreClean) {
  const Scene example = load_scene(scene_data_dir() + "/example.yaml");
  EXPECT_TRUE(warnings_of(example).empty());
  const Scene builtin =
      load_scene(std::string(TALUS_SOURCE_DIR) + "/validation/dodecahedron_packing/scene.yaml");
  EXPECT_TRUE(warnings_of(builtin).empty());
}

}  // namespace
}  // namespace talus
