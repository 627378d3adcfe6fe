// Poured beds on the host backend (issue 15, the production code): 216 particles of 10 mm (E =
// 5 MPa, density 1200, mu 0.4, eps 0.5) dropped from a lattice into an open box with random
// orientations, friction and rotation, at dt = 1e-5 s. With the default volume law each bed comes
// to rest: by 0.6 s its kinetic energy is below 1e-4 of the gravitational energy it released, and
// no particle is thrown above the bed. Cubes, tetrahedra, the mineral shape and the paper's
// 20-sided cylinder scaled to 10 mm (measured here: 2.7e-7, 1.2e-8, 1.3e-11 and 9.7e-7 of the
// released energy left). (The paper's law, contact: volume_paper, keeps 2e-3 to 8e-3 of it at
// 1 s in the 8,700-particle beds of experiments/beds.) The cylinders' 8,700-particle bed stopped
// on a degenerate overlap of two prisms on the GPU, still to be found; this one does not.
#include <gtest/gtest.h>

#include <string>

#include "solver/step/host/host_step.hpp"
#include "tests/step/step_test_util.hpp"

namespace talus {
namespace {

struct BedCase {
  std::string name, shape;
};

void PrintTo(const BedCase& c, std::ostream* os) {
  *os << c.name;
}

class PouredBeds : public ::testing::TestWithParam<BedCase> {};

TEST_P(PouredBeds, ComeToRestWithNothingAboveTheBed) {
  const BedCase& c = GetParam();
  // 6 x 6 x 6 lattice sites 11 mm apart (one circumscribed diameter and a gap) in a 66 mm box.
  const Scene scene = talus_test::scene_from(
      "time: {step: 1.0e-5, end: 0.6}\n"
      "materials:\n"
      "  grain: {density: 1200, youngs_modulus: 5.0e6, poisson_ratio: 0.3, friction: 0.4,\n"
      "          restitution: 0.5}\n"
      "templates:\n"
      "  p: {shape: \"" +
      c.shape +
      "\", material: grain}\n"
      "particles:\n"
      "  - lattice: {template: p, region: {box: {min: [0, 0, 0.002], max: [0.066, 0.066, "
      "0.0686]}}, spacing: 0.011, random_orientation: true, seed: 7}\n"
      "walls:\n"
      "  - box: {min: [0, 0, 0], max: [0.066, 0.066, 0.2], open_top: true, material: grain}\n"
      "effects:\n"
      "  gravity: [0, 0, -9.81]\n"
      "  contact: volume\n"
      "  friction: true\n"
      "  rotation: true\n");
  HostStep<double> step(scene, 1);
  ASSERT_EQ(step.particle_count(), 216);
  step.evaluate_forces();
  const double start = step.energy().gravitational;
  while (step.time() < scene.end_time - 0.5 * scene.time_step) step.step();
  const EnergyTerms end = step.energy();
  const double released = start - end.gravitational;
  ASSERT_GT(released, 0.0);
  // The criterion: the kinetic energy below 1e-4 of the released potential energy.
  EXPECT_LT(end.kinetic(), 1e-4 * released) << c.name;
  // Nothing above the bed: the highest particle top below the height the particles' volume fills
  // at a solid fraction of 0.35 (looser than any of these beds, 0.55-0.65 in experiments/beds),
  // plus one diameter. A particle thrown out of the bed would be far above it.
  double volume = 0;
  for (const ParticleTemplate& t : scene.templates) volume = t.volume;
  const double fill = 216 * volume / (0.066 * 0.066 * 0.35);
  EXPECT_LT(step.bed_height(Vec3d(0, 0, -9.81)), fill + 0.01) << c.name;
  std::printf("%s: kinetic %.3g J of %.3g J released, bed %.4g m (bound %.4g m)\n", c.name.c_str(),
              end.kinetic(), released, step.bed_height(Vec3d(0, 0, -9.81)), fill + 0.01);
}

INSTANTIATE_TEST_SUITE_P(, PouredBeds,
                         ::testing::Values(BedCase{"Cubes", "cube:0.01"},
                                           BedCase{"Tetrahedra", "tetrahedron:0.01"},
                                           BedCase{"Minerals", "mineral:0.01"},
                                           BedCase{"Cylinders", "cylinder:0.00834,0.00552,20"}),
                         [](const ::testing::TestParamInfo<BedCase>& info) {
                           return info.param.name;
                         });

}  // namespace
}  // namespace talus
