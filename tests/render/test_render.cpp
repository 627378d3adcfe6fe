// `talus render`'s pieces: the projection, and a run drawn to PNG whose particle table is checked
// against the pixels (id colours), its painter's order and its errors.
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "solver/io/output_files.hpp"
#include "solver/io/trajectory.hpp"
#include "solver/render/frame_drawing.hpp"
#include "solver/render/projection.hpp"
#include "solver/render/render_run.hpp"
#include "tests/support/json_test_util.hpp"
#include "tests/support/test_files.hpp"

namespace talus {
namespace {

using talus_test::fresh_test_directory;
using talus_test::read_text;
using talus_test::write_text;

TEST(RenderProjection, ViewsAreRightHandedAndLookAlongTheirAxis) {
  for (const char* name : {"x", "-x", "y", "-y", "z", "-z"}) {
    const ViewAxes v = view_axes(name);
    const Vec3d c = cross(v.right, v.up);
    EXPECT_NEAR(norm(c - v.toward_viewer), 0, 1e-15) << name;
    EXPECT_NEAR(dot(v.right, v.up), 0, 1e-15) << name;
  }
  // Looking along +y: x to the right, z up (the side view of a pile under -z gravity).
  const ViewAxes y = view_axes("y");
  EXPECT_EQ(y.right.x, 1);
  EXPECT_EQ(y.up.z, 1);
  EXPECT_EQ(y.toward_viewer.y, -1);
  EXPECT_THROW(view_axes("w"), std::invalid_argument);
}

TEST(RenderProjection, FitCentresTheExtentInsideTheMargins) {
  const ViewAxes v = view_axes("y");
  // 0.2 m wide, 0.1 m tall into 420 x 220 px with 10 px margins: 400 / 0.2 = 2000 px/m and
  // 200 / 0.1 = 2000 px/m minus the one pixel between first and last centres: 1995 px/m.
  const Projection p = fit_projection(v, {{-0.1, 5, 0}, {0.1, 0, 0.1}}, 420, 220, 10);
  EXPECT_DOUBLE_EQ(p.pixels_per_metre, 199 / 0.1);
  const PixelPoint low = p.project({-0.1, 0, 0}), high = p.project({0.1, 0, 0.1});
  EXPECT_NEAR(low.row, 219 - 10 - 0.5 * (199 - 0.1 * p.pixels_per_metre), 1e-9);
  EXPECT_NEAR(high.row, 10, 1e-9);
  EXPECT_NEAR(low.column + high.column, 419, 1e-9);  // centred
  EXPECT_NEAR(p.project({0, 7, 0}).depth, -7, 0);    // toward_viewer is -y
}

// A run directory made by hand: a scene of dodecahedra, run.json and one trajectory frame.
struct HandRun {
  std::string dir;
  std::vector<TrajectoryRow> rows;
};

HandRun make_run(const std::string& name, const std::vector<Vec3d>& positions) {
  HandRun run;
  run.dir = fresh_test_directory("render", name);
  write_text(run.dir + "/scene.yaml",
             "time: {step: 1.0e-4, end: 1.0e-3}\n"
             "materials:\n"
             "  m: {density: 1500, youngs_modulus: 1.0e6, poisson_ratio: 0.1, friction: 0.5,\n"
             "      restitution: 0.5}\n"
             "templates:\n"
             "  d: {shape: dodecahedron:0.03, material: m}\n"
             "particles:\n"
             "  - explicit:\n"
             "      - {template: d, position: [0, 0, 0]}\n");
  write_run_info(run.dir, {run.dir + "/scene.yaml", "talus", "double", 1e-4, {"d"}});
  long long id = 10;
  for (const Vec3d& p : positions) {
    TrajectoryRow row;
    row.id = id++;
    row.position = p;
    const double angle = 0.3 * double(id);
    row.orientation = Quatd{std::cos(angle), 0.6 * std::sin(angle), 0.8 * std::sin(angle), 0};
    row.velocity = {0, 0, -0.1 * double(id)};
    run.rows.push_back(row);
  }
  write_trajectory_frame(run.dir, 40, run.rows);
  return run;
}

struct CentreRow {
  long long id;
  double column, row, depth;
  long long visible;
};

std::vector<CentreRow> read_centres(const std::string& path) {
  std::vector<CentreRow> rows;
  std::istringstream in(read_text(path));
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "id,template,column,row,depth,visible_pixels");
  while (std::getline(in, line)) {
    CentreRow r{};
    int template_id = 0;
    EXPECT_EQ(std::sscanf(line.c_str(), "%lld,%d,%lf,%lf,%lf,%lld", &r.id, &template_id, &r.column,
                          &r.row, &r.depth, &r.visible),
              6)
        << line;
    rows.push_back(r);
  }
  return rows;
}

// The tracker's contract: the table's (column, row) of a particle is where its id colour sits.
// A regular dodecahedron is centrally symmetric, so its outline, whatever its orientation, is
// symmetric about the projected centre, and the centroid of its pixels is that centre up to the
// raster's rounding along the outline (the corners are placed to 1/16 px; a pixel is in when
// its centre is, so the error along an edge averages out): 0.25 px at ~60 px across.
TEST(RenderRun, ParticleTableMatchesTheIdColouredPixels) {
  const HandRun run =
      make_run("centres", {{-0.05, 0, 0.01}, {0.04, 0.02, -0.02}, {0, -0.01, 0.06}});
  RenderSettings settings;
  settings.run_directory = run.dir;
  settings.color = ColorMode::id;
  settings.width = 400;
  settings.height = 300;
  settings.label = false;
  const RenderReport report = render_run(settings);
  ASSERT_EQ(report.images.size(), 1u);
  EXPECT_EQ(report.output_directory, run.dir + "/render");
  const cv::Mat image = cv::imread(run.dir + "/render/frame_000000040.png", cv::IMREAD_COLOR);
  ASSERT_EQ(image.cols, 400);
  ASSERT_EQ(image.rows, 300);
  const std::vector<CentreRow> table = read_centres(run.dir + "/render/frame_000000040.csv");
  ASSERT_EQ(table.size(), 3u);
  for (std::size_t k = 0; k < table.size(); ++k) {
    const Rgb colour = id_color(table[k].id);
    double sum_c = 0, sum_r = 0;
    long long count = 0;
    for (int r = 0; r < image.rows; ++r)
      for (int c = 0; c < image.cols; ++c) {
        const cv::Vec3b bgr = image.at<cv::Vec3b>(r, c);
        if (bgr[2] == colour.r && bgr[1] == colour.g && bgr[0] == colour.b) {
          sum_c += c;
          sum_r += r;
          ++count;
        }
      }
    ASSERT_GT(count, 0) << "id " << table[k].id;
    EXPECT_NEAR(sum_c / count, table[k].column, 0.25) << "id " << table[k].id;
    EXPECT_NEAR(sum_r / count, table[k].row, 0.25) << "id " << table[k].id;
    // No wall lines and no overlap here: every pixel of the particle shows its colour.
    EXPECT_EQ(count, table[k].visible) << "id " << table[k].id;
    // The pixels of the outline's area: a dodecahedron of circumradius R = 15 mm shows between
    // the area of its insphere's disc (r = 0.794 R) and of its circumsphere's.
    const double s = report.projection.pixels_per_metre, R = 0.015;
    EXPECT_GT(count, 3.14159 * std::pow(0.794 * R * s, 2)) << "id " << table[k].id;
    EXPECT_LT(count, 3.14159 * std::pow(R * s, 2)) << "id " << table[k].id;
    // Back to metres through render.json's numbers.
    const Vec3d& x = run.rows[k].position;
    EXPECT_NEAR((table[k].column - report.projection.origin_column) / s, x.x, 1e-12);
    EXPECT_NEAR((report.projection.origin_row - table[k].row) / s, x.z, 1e-12);
  }
  talus_test::Json json = talus_test::parse_or_fail(read_text(run.dir + "/render/render.json"));
  EXPECT_EQ(json["pixels_per_metre"].get<double>(), report.projection.pixels_per_metre);
  EXPECT_EQ(json["origin_pixel"][0].get<double>(), report.projection.origin_column);
  ASSERT_EQ(json["frames"].size(), 1u);
  EXPECT_EQ(json["frames"][0]["image"].get<std::string>(), "frame_000000040.png");
  EXPECT_FALSE(std::filesystem::exists(run.dir + "/render/frame_000000040.png.tmp"));
}

// Painter's order: of two particles on one line of sight, the nearer one owns the middle.
TEST(RenderRun, NearerParticleHidesTheFartherOne) {
  // Looking along +y: the one at y = -0.05 is nearer the camera.
  const HandRun run = make_run("painter", {{0, 0.05, 0}, {0.005, -0.05, 0}});
  RenderSettings settings;
  settings.run_directory = run.dir;
  settings.color = ColorMode::id;
  settings.label = false;
  render_run(settings);
  const std::vector<CentreRow> table = read_centres(run.dir + "/render/frame_000000040.csv");
  const cv::Mat image = cv::imread(run.dir + "/render/frame_000000040.png", cv::IMREAD_COLOR);
  const cv::Vec3b middle =
      image.at<cv::Vec3b>(int(std::lround(table[1].row)), int(std::lround(table[1].column)));
  const Rgb near = id_color(table[1].id);
  EXPECT_EQ(middle[2], near.r);
  EXPECT_EQ(middle[1], near.g);
  EXPECT_EQ(middle[0], near.b);
  EXPECT_LT(table[0].visible, table[1].visible / 2);  // mostly hidden
  EXPECT_GT(table[1].depth, table[0].depth);
}

// --outline: the nearer particle's silhouette runs across the farther one, so the two are
// parted by a line of the outline colour along the row through both centres; without it, that
// row goes from one particle's colour to the other's with no such pixel between them.
TEST(RenderRun, OutlineShowsWhereANearerParticleHidesAFartherOne) {
  // Looking along +y, 20 mm apart in x: the 30 mm dodecahedra overlap by about 5 mm.
  const HandRun run = make_run("outline", {{0, 0.05, 0}, {0.02, -0.05, 0}});
  for (const bool outline : {false, true}) {
    RenderSettings settings;
    settings.run_directory = run.dir;
    settings.label = false;
    settings.outline = outline;
    settings.output_directory = run.dir + (outline ? "/outlined" : "/plain");
    render_run(settings);
    const std::vector<CentreRow> table =
        read_centres(settings.output_directory + "/frame_000000040.csv");
    const cv::Mat image =
        cv::imread(settings.output_directory + "/frame_000000040.png", cv::IMREAD_COLOR);
    const int row = int(std::lround(table[1].row));
    int dark = 0;
    for (int c = int(std::lround(table[0].column)); c <= int(std::lround(table[1].column)); ++c) {
      const cv::Vec3b p = image.at<cv::Vec3b>(row, c);
      dark += p[2] == kOutlineColor.r && p[1] == kOutlineColor.g && p[0] == kOutlineColor.b;
    }
    if (outline)
      EXPECT_GE(dark, 1) << "no outline between the two particles";
    else
      EXPECT_EQ(dark, 0) << "an outline pixel without --outline";
  }
}

TEST(RenderRun, BadInputNamesTheFileAndWhatWasExpected) {
  RenderSettings settings;
  settings.run_directory = "/nonexistent/talus-run";
  try {
    render_run(settings);
    ADD_FAILURE() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/talus-run: no such directory"),
              std::string::npos)
        << e.what();
  }
  const std::string empty = fresh_test_directory("render", "empty");
  settings.run_directory = empty;
  try {
    render_run(settings);
    ADD_FAILURE() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("no run.json"), std::string::npos) << e.what();
  }
  const HandRun run = make_run("no_frames", {});
  std::filesystem::remove(run.dir + "/trajectory_000000040.csv");
  settings.run_directory = run.dir;
  try {
    render_run(settings);
    ADD_FAILURE() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("no trajectory_<step>.csv or .h5 files"),
              std::string::npos)
        << e.what();
  }
  settings.scene_file = run.dir + "/missing.yaml";
  write_trajectory_frame(run.dir, 0, {});
  try {
    render_run(settings);
    ADD_FAILURE() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("missing.yaml' is not found"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace talus
