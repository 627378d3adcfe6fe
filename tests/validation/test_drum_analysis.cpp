// The drum case's measures (validation/rotating_drum/drum_analysis.hpp) on point sets whose
// answers are known, and its particle detection (image_tracking.hpp, where OpenCV is built in)
// on pictures drawn by talus render's code from particles placed by hand.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "validation/rotating_drum/drum_analysis.hpp"

#if TALUS_HAVE_OPENCV
#include "solver/io/output_files.hpp"
#include "solver/io/vtk_output.hpp"
#include "solver/render/frame_drawing.hpp"
#include "solver/render/frame_image.hpp"
#include "solver/scene/scene_loader.hpp"
#include "tests/support/test_files.hpp"
#include "validation/rotating_drum/image_tracking.hpp"
#endif

namespace talus::validation {
namespace {

constexpr double kPi = 3.14159265358979323846;

TEST(DrumVelocityField, AveragesPerCellAndIgnoresWhatLiesOutside) {
  VelocityField field(4, 0.01);  // 4 x 4 cells of 1 cm, from -2 cm to 2 cm
  field.add({-0.015, -0.015}, 1.0, 2.0);
  field.add({-0.012, -0.019}, 3.0, 4.0);  // the same cell
  field.add({0.005, 0.015}, -1.0, 0.5);
  field.add({0.021, 0.0}, 9.0, 9.0);  // outside
  field.add({std::nan(""), 0.0}, 9.0, 9.0);
  EXPECT_EQ(field.count(0, 0), 2);
  EXPECT_DOUBLE_EQ(field.mean_u(0, 0), 2.0);
  EXPECT_DOUBLE_EQ(field.mean_w(0, 0), 3.0);
  EXPECT_EQ(field.count(2, 3), 1);
  EXPECT_DOUBLE_EQ(field.mean_u(2, 3), -1.0);
  long long total = 0;
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i) total += field.count(i, j);
  EXPECT_EQ(total, 3);
  EXPECT_NEAR(field.centre(0, 0).a, -0.015, 1e-15);
  EXPECT_NEAR(field.centre(2, 3).b, 0.015, 1e-15);
  EXPECT_DOUBLE_EQ(field.mean_u(1, 1), 0.0);  // no sample
}

TEST(DrumVelocityField, RSquaredCountsBothComponentsOverSharedCells) {
  VelocityField truth(3, 1.0), measured(3, 1.0);
  // Three cells along the bottom row with u = 1, 2, 3 and w = 0 in the truth; the measurement
  // is off by 1 in the last cell's u. R^2 = 1 - 1 / ((1-2)^2 + 0 + (3-2)^2) = 0.5.
  for (int i = 0; i < 3; ++i) {
    const PlanePoint at = truth.centre(i, 0);
    for (int k = 0; k < 2; ++k) {
      truth.add(at, 1.0 + i, 0.0);
      measured.add(at, i == 2 ? 4.0 : 1.0 + i, 0.0);
    }
  }
  // A cell only the truth has, and one with too few samples in the measurement: both left out.
  truth.add(truth.centre(1, 2), 50.0, 50.0);
  truth.add(truth.centre(1, 2), 50.0, 50.0);
  truth.add(truth.centre(2, 2), 50.0, 50.0);
  truth.add(truth.centre(2, 2), 50.0, 50.0);
  measured.add(truth.centre(2, 2), -50.0, 0.0);
  int used = 0;
  EXPECT_NEAR(field_r_squared(measured, truth, 2, &used), 0.5, 1e-12);
  EXPECT_EQ(used, 3);
  EXPECT_NEAR(field_r_squared(truth, truth, 2), 1.0, 1e-15);
  EXPECT_TRUE(std::isnan(field_r_squared(measured, truth, 3)));  // no cell has 3 in both
}

// A bed of centres on a square lattice of pitch h below the line b = tan(angle) a, over the
// lower half of a disc of radius R.
std::vector<PlanePoint> tilted_bed(double angle_deg, double h, double radius) {
  const double slope = std::tan(angle_deg * kPi / 180);
  std::vector<PlanePoint> bed;
  for (double a = -radius; a <= radius; a += h)
    for (double b = -radius; b <= slope * a; b += h)
      if (std::hypot(a, b) < radius) bed.push_back({a, b});
  return bed;
}

TEST(DrumReposeAngle, RecoversTheSlopeOfTheSurfaceAndSkipsParticlesInFlight) {
  // Tops of each strip lie within one pitch (1 mm) below the line: over the middle half of a
  // 0.15 m drum (15 strips of 5 mm) the fitted slope is off by well under a degree.
  for (const double angle : {25.0, 40.0}) {
    std::vector<PlanePoint> bed = tilted_bed(angle, 0.001, 0.15);
    EXPECT_NEAR(repose_angle(bed, 0.005, 0.075, 0.0015), angle, 0.5) << angle;
    // Particles in flight high over the left end (nothing within 1.5 mm of each) change
    // nothing; counted as the tops of their strips, they would tilt the line by degrees.
    for (const double a : {-0.072, -0.066, -0.06}) bed.push_back({a, 0.12});
    EXPECT_NEAR(repose_angle(bed, 0.005, 0.075, 0.0015), angle, 0.5) << angle;
    EXPECT_GT(std::abs(repose_angle(bed, 0.005, 0.075, 1.0) - angle), 2.0) << angle;
  }
  EXPECT_TRUE(std::isnan(repose_angle({{0, 0}, {0.0001, 0}}, 0.005, 0.075, 0.001)));
}

TEST(DrumHighestLift, TakesTheHighestCentreNearTheWallOnTheRisingSide) {
  const double radius = 0.15;
  const auto at = [&](double elevation_deg, double r, double side) {
    const double e = elevation_deg * kPi / 180;
    return PlanePoint{side * r * std::cos(e), r * std::sin(e)};
  };
  const std::vector<PlanePoint> centres = {at(-40, 0.145, 1),
                                           at(20, 0.142, 1),  // rising side (right), near the wall
                                           at(35, 0.12, 1),   // higher, but 3 cm in from the wall
                                           at(60, 0.146, -1)};  // higher, on the other side
  EXPECT_NEAR(highest_lift(centres, radius, 0.01, true), 20.0, 1e-9);
  EXPECT_NEAR(highest_lift(centres, radius, 0.01, false), 60.0, 1e-9);
  EXPECT_EQ(highest_lift({at(10, 0.1, 1)}, radius, 0.01, true), -90);
}

TEST(DrumTracking, MatchesMutualNearestNeighboursWithinTheGate) {
  const std::vector<PlanePoint> from = {{0, 0}, {0.01, 0}, {0.05, 0.05}};
  const std::vector<PlanePoint> to = {{0.0101, 0.0002}, {0.0003, -0.0001}, {0.08, 0.05}};
  const auto pairs = match_nearest(from, to, 0.005);
  ASSERT_EQ(pairs.size(), 2u);  // the third is 3 cm from its nearest: beyond the gate
  EXPECT_EQ(pairs[0], std::make_pair(0, 1));
  EXPECT_EQ(pairs[1], std::make_pair(1, 0));
  // Two points whose nearest is the same one: only the nearer of the two is paired.
  const auto shared = match_nearest({{0, 0}, {0.002, 0}}, {{0.0015, 0}}, 0.005);
  ASSERT_EQ(shared.size(), 1u);
  EXPECT_EQ(shared[0].first, 1);
}

#if TALUS_HAVE_OPENCV

// Dodecahedra of 1 cm in a monolayer, some touching, drawn as the drum case draws them (960 px,
// 31 px a particle): every particle is found, each centroid within a pixel of its centre.
TEST(DrumDetection, FindsEachDodecahedronOfAPictureAtItsCentre) {
  const std::string dir = talus_test::fresh_test_directory("drum-detection", "touching");
  talus_test::write_text(
      dir + "/scene.yaml",
      "time: {step: 1.0e-5, end: 1.0e-4}\n"
      "materials:\n"
      "  resin: {density: 1500, youngs_modulus: 1.0e6, poisson_ratio: 0.1, friction: 0.7,\n"
      "          restitution: 0.1}\n"
      "templates:\n"
      "  d: {shape: \"dodecahedron:0.01\", material: resin}\n"
      "particles:\n"
      "  - explicit:\n"
      "      - {template: d, position: [0, 0, 0]}\n");
  const Scene scene = load_scene(dir + "/scene.yaml");
  const std::vector<TemplateSurface> surfaces = {template_surface(scene.templates.at(0))};
  std::mt19937_64 random(5);
  std::uniform_real_distribution<double> unit(-1, 1);
  std::vector<TrajectoryRow> rows;
  // A 6 x 5 block at 8.5 mm pitch (touching or nearly: the dodecahedron is 7.9 to 10 mm wide),
  // randomly turned and shifted by up to 0.5 mm, and a few apart.
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 5; ++j) {
      TrajectoryRow row;
      row.id = static_cast<long long>(rows.size());
      row.position = {-0.1 + 0.0085 * i + 0.0005 * unit(random), 0.0005 * unit(random),
                      -0.05 + 0.0085 * j + 0.0005 * unit(random)};
      row.orientation = Quatd(unit(random), unit(random), unit(random), unit(random)).normalized();
      rows.push_back(row);
    }
  for (int k = 0; k < 4; ++k) {
    TrajectoryRow row;
    row.id = static_cast<long long>(rows.size());
    row.position = {0.03 * k, 0, 0.08};
    row.orientation = Quatd(1, unit(random), unit(random), unit(random)).normalized();
    rows.push_back(row);
  }
  const ViewAxes axes = view_axes("y");
  const Projection projection =
      fit_projection(axes, {{-0.15, 0, -0.15}, {0.15, 0, 0.15}}, 960, 960, 16);
  const FrameDrawing drawing = draw_frame(projection, surfaces, rows, {}, DrawSettings{});
  const FrameImage picture = render_frame_image(drawing, 960, 960, rows.size(), "");
  write_file_atomically(dir + "/frame.png", picture.png);

  DetectionSettings settings;
  settings.inradius = 0.7947 * 0.005 * projection.pixels_per_metre;
  const std::vector<ImageDetection> found = detect_particles(dir + "/frame.png", settings);
  EXPECT_EQ(found.size(), rows.size());
  std::vector<PlanePoint> truth, seen;
  for (const TrajectoryRow& r : rows) {
    const PixelPoint p = projection.project(r.position);
    truth.push_back({p.column, p.row});
  }
  for (const ImageDetection& d : found) seen.push_back({d.column, d.row});
  const auto pairs = match_nearest(truth, seen, 5.0);
  EXPECT_EQ(pairs.size(), rows.size());
  // A centrally symmetric particle's image has its centre as centroid. At 8.5 mm pitch the
  // block's neighbours overlap in the picture (up to 10 mm wide): the nearer hides a sliver of
  // the farther, and the split between touching ones follows the nearest seed, each shifting a
  // centroid by a pixel or so. The median within half a pixel, each within a tenth of a
  // particle (3.1 px), the drum case's tolerance on the median.
  std::vector<double> errors;
  for (const auto& [t, s] : pairs) {
    errors.push_back(std::hypot(truth[t].a - seen[s].a, truth[t].b - seen[s].b));
    EXPECT_LT(errors.back(), 0.1 * 0.01 * projection.pixels_per_metre) << "particle " << t;
  }
  std::sort(errors.begin(), errors.end());
  EXPECT_LT(errors[errors.size() / 2], 0.5);
}

TEST(DrumDetection, AnUnreadableFileIsNamed) {
  const std::string dir = talus_test::fresh_test_directory("drum-detection", "unreadable");
  talus_test::write_text(dir + "/frame.png", "not a picture");
  try {
    detect_particles(dir + "/frame.png", DetectionSettings{});
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(dir + "/frame.png: cannot be read as an image"),
              std::string::npos)
        << e.what();
  }
}

#endif

}  // namespace
}  // namespace talus::validation
