// The `talus` command line, run as a separate process: its JSON against closed-form overlaps of
// cubes, and its exit codes and messages for each class of bad argument.
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "tests/app/run_talus.hpp"
#include "tests/support/json_test_util.hpp"
#include "tests/support/test_files.hpp"

namespace {

using talus_test::Json;
using talus_test::parse_or_fail;
using talus_test::ProcessResult;
using talus_test::read_file;
using talus_test::run_talus;

// ---- Shapes and poses

// Circumscribed diameter of the test cube (m) and its side d / sqrt(3).
constexpr double kCubeDiameter = 0.01;
const double kSide = kCubeDiameter / std::sqrt(3.0);
const std::string kCube = "cube:0.01";

// The overlap is a sum of a few dozen cone volumes and face areas, each exact to a few ulps, and
// the printed numbers round-trip exactly (17 digits): 1e-12 relative is ~4 orders above round-off
// and far below any real error (a wrong face or a missing cone is an O(1) error).
constexpr double kRelTol = 1e-12;

std::string number_text(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.17g", v);
  return buffer;
}

std::string pose_text(double x, double y, double z, double qw = 1, double qx = 0, double qy = 0,
                      double qz = 0) {
  return number_text(x) + "," + number_text(y) + "," + number_text(z) + "," + number_text(qw) +
         "," + number_text(qx) + "," + number_text(qy) + "," + number_text(qz);
}

const std::string kAtOrigin = "0,0,0,1,0,0,0";

Json overlap(const std::string& pose_a, const std::string& pose_b) {
  const ProcessResult run = run_talus({"overlap", kCube, pose_a, kCube, pose_b});
  EXPECT_EQ(run.exit_code, 0) << run.err;
  return parse_or_fail(run.out);
}

void expect_vec(const Json& v, double x, double y, double z, double tol, const char* what) {
  ASSERT_TRUE(v.is_array()) << what;
  ASSERT_EQ(v.size(), 3u) << what;
  EXPECT_NEAR(v[0].get<double>(), x, tol) << what;
  EXPECT_NEAR(v[1].get<double>(), y, tol) << what;
  EXPECT_NEAR(v[2].get<double>(), z, tol) << what;
}

// ---- Overlap of two cubes: closed forms

// Offset along one axis: the overlap is the box s^2 (s - |d|); S is A's face towards B (the four
// side faces are shared by both cubes, count half to each and cancel in pairs), so n = +-e_axis
// and |S| = s^2; the centroid is at d/2.
TEST(TalusOverlap, CubesOffsetAlongEachAxis) {
  for (int axis = 0; axis < 3; ++axis) {
    for (const double sign : {1.0, -1.0}) {
      double d[3] = {0, 0, 0};
      d[axis] = sign * 0.3 * kSide;
      Json r = overlap(kAtOrigin, pose_text(d[0], d[1], d[2]));
      EXPECT_EQ(r["status"].get<std::string>(), "overlapping");
      const double volume = kSide * kSide * (kSide - std::abs(d[axis]));
      EXPECT_NEAR(r["volume"].get<double>(), volume, kRelTol * volume) << "axis " << axis;
      expect_vec(r["normal"], axis == 0 ? sign : 0, axis == 1 ? sign : 0, axis == 2 ? sign : 0,
                 kRelTol, "normal");
      EXPECT_NEAR(r["area"].get<double>(), kSide * kSide, kRelTol * kSide * kSide);
      expect_vec(r["point"], d[0] / 2, d[1] / 2, d[2] / 2, kRelTol * kSide, "point");
      EXPECT_TRUE(r["gjk_intersecting"].get<bool>());
      // The simple model's penetration depth along the axis is s - |d|.
      EXPECT_NEAR(r["depth"].get<double>(), kSide - std::abs(d[axis]), kRelTol * kSide);
      EXPECT_EQ(r["a"].get<std::string>(), kCube);
      EXPECT_EQ(r["b"].get<std::string>(), kCube);
    }
  }
}

// Offset on all three axes: the box (s-|dx|)(s-|dy|)(s-|dz|); S is the sum of the three faces of A
// that bound it, each along sign(d_i) with the area of the box's face across that axis.
TEST(TalusOverlap, CubesOffsetOnThreeAxesGiveBoxVolumeAndVectorArea) {
  const double d[3] = {0.2 * kSide, -0.35 * kSide, 0.5 * kSide};
  const double e[3] = {kSide - 0.2 * kSide, kSide - 0.35 * kSide, kSide - 0.5 * kSide};
  Json r = overlap(kAtOrigin, pose_text(d[0], d[1], d[2]));
  EXPECT_EQ(r["status"].get<std::string>(), "overlapping");
  const double volume = e[0] * e[1] * e[2];
  EXPECT_NEAR(r["volume"].get<double>(), volume, kRelTol * volume);
  const double s[3] = {e[1] * e[2], -e[0] * e[2], e[0] * e[1]};
  const double area = std::sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
  expect_vec(r["vector_area"], s[0], s[1], s[2], kRelTol * area, "vector_area");
  EXPECT_NEAR(r["area"].get<double>(), area, kRelTol * area);
  expect_vec(r["normal"], s[0] / area, s[1] / area, s[2] / area, kRelTol, "normal");
  expect_vec(r["point"], d[0] / 2, d[1] / 2, d[2] / 2, kRelTol * kSide, "point");
  // Six planes meeting three at each corner: the vertex enumeration's case; the inradius (the
  // LP's, run again for this key) is half the box's shortest side.
  EXPECT_TRUE(r["enumerated"].is_boolean());
  EXPECT_TRUE(r["enumerated"].get<bool>());
  EXPECT_NEAR(r["chebyshev_depth"].get<double>(), e[2] / 2, kRelTol * kSide);
}

// B turned 45 degrees about z with a vertical edge pushed a depth p into A's +x face: the overlap
// is a prism over the triangle of height p and base 2p (area p^2), of length s; S = 2ps e_x (the
// z faces are shared and cancel); the centroid sits p/3 inside the face. The simple model's
// depth is p along +x, its point midway into the penetration on the edge's line.
TEST(TalusOverlap, RotatedCubeEdgeIntoFace) {
  const double p = 0.2 * kSide;
  const double half_diagonal = kSide / std::sqrt(2.0);
  const double x = kSide / 2 + half_diagonal - p;
  const double angle = M_PI / 4;
  Json r = overlap(kAtOrigin, pose_text(x, 0, 0, std::cos(angle / 2), 0, 0, std::sin(angle / 2)));
  EXPECT_EQ(r["status"].get<std::string>(), "overlapping");
  EXPECT_NEAR(r["volume"].get<double>(), p * p * kSide, kRelTol * p * p * kSide);
  expect_vec(r["normal"], 1, 0, 0, kRelTol, "normal");
  EXPECT_NEAR(r["area"].get<double>(), 2 * p * kSide, kRelTol * p * kSide);
  expect_vec(r["point"], kSide / 2 - p / 3, 0, 0, kRelTol * kSide, "point");
  EXPECT_NEAR(r["depth"].get<double>(), p, kRelTol * kSide);
  expect_vec(r["simple_normal"], 1, 0, 0, kRelTol, "simple_normal");
  expect_vec(r["simple_point"], kSide / 2 - p / 2, 0, 0, kRelTol * kSide, "simple_point");
  // The z faces are twins (coplanar faces of A and B): the enumeration declines, the hull
  // answers. The inradius is the prism's triangle's: legs p sqrt(2), hypotenuse 2p, so
  // (2 p sqrt(2) - 2p) / 2.
  EXPECT_TRUE(r["enumerated"].is_boolean());
  EXPECT_FALSE(r["enumerated"].get<bool>());
  EXPECT_NEAR(r["chebyshev_depth"].get<double>(), p * (std::sqrt(2.0) - 1), kRelTol * kSide);
}

// The same box overlap far from the world origin: talus works relative to A, so only the
// decimal positions' own rounding (~1e-16 m at 1 m, i.e. ~2e-14 of the side) enters.
TEST(TalusOverlap, TranslationOfBothCubesChangesNothing) {
  const double origin[3] = {1.25, -2.5, 0.75};
  const double d = 0.3 * kSide;
  Json r = overlap(pose_text(origin[0], origin[1], origin[2]),
                   pose_text(origin[0] + d, origin[1], origin[2]));
  const double actual_d = (origin[0] + d) - origin[0];
  const double volume = kSide * kSide * (kSide - actual_d);
  EXPECT_NEAR(r["volume"].get<double>(), volume, kRelTol * volume);
  expect_vec(r["point"], origin[0] + actual_d / 2, origin[1], origin[2], 1e-12, "point");
}

// A face-to-face slab 2.8e-11 m deep with a tilt of 9.4e-9 rad (found by sampling such pairs as
// tests/geometry/test_overlap_thin_slabs.cpp does): its dual hull fails at an inradius of 2.9e-13
// m, far below the thin-slab limit 8 sqrt(eps) R = 6e-10 m, so the pair is touching with no
// volume and says why; before the rule such pairs stopped a run as degenerate or, where the hull
// "succeeded", gave volumes of cubic metres. A plain overlap is no thin slab.
TEST(TalusOverlap, AThinFaceToFaceSlabIsTouchingAndSaysSo) {
  Json r = overlap(kAtOrigin,
                   "0.0057735026637938383,5.0912288945520467e-05,4.5066892802697513e-05,"
                   "-0.86909302021217538,0.49464868565324149,4.6724713684524375e-09,"
                   "3.8010973285262983e-10");
  EXPECT_EQ(r["status"].get<std::string>(), "touching");
  EXPECT_TRUE(r["thin_slab"].get<bool>());
  EXPECT_EQ(r["volume"].get<double>(), 0);
  EXPECT_LT(r["chebyshev_depth"].get<double>(), 6e-10);
  EXPECT_TRUE(r["gjk_intersecting"].get<bool>());
  Json plain = overlap(kAtOrigin, pose_text(0.3 * kSide, 0, 0));
  EXPECT_EQ(plain["status"].get<std::string>(), "overlapping");
  EXPECT_FALSE(plain["thin_slab"].get<bool>());
}

TEST(TalusOverlap, SeparateCubesReportNothing) {
  // Along x beyond contact, and a diagonal placement where the bounding spheres overlap
  // (1.16 s < 2 * 0.866 s) so that only the polyhedra can say "separate".
  const std::vector<std::string> poses = {pose_text(1.5 * kSide, 0, 0),
                                          pose_text(1.05 * kSide, 0.5 * kSide, 0)};
  for (const std::string& pose : poses) {
    Json r = overlap(kAtOrigin, pose);
    EXPECT_EQ(r["status"].get<std::string>(), "separate") << pose;
    EXPECT_EQ(r["volume"].get<double>(), 0);
    expect_vec(r["normal"], 0, 0, 0, 0, "normal");
    EXPECT_EQ(r["area"].get<double>(), 0);
    EXPECT_FALSE(r["gjk_intersecting"].get<bool>());
    EXPECT_EQ(r["depth"].get<double>(), 0);
    EXPECT_FALSE(r["simple_touching"].get<bool>());
  }
}

// Positions whose difference overflows make the simple model's normal non-finite; the output must
// stay valid JSON (null in place of the number).
TEST(TalusOverlap, NonFiniteIntermediatesStillGiveValidJson) {
  Json r = overlap(pose_text(-1e308, 0, 0), pose_text(1e308, 0, 0));
  EXPECT_EQ(r["status"].get<std::string>(), "separate");
}

// ---- talus shape

TEST(TalusShape, CubeTemplate) {
  const ProcessResult run = run_talus({"shape", kCube});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  Json r = parse_or_fail(run.out);
  const double volume = kSide * kSide * kSide;
  EXPECT_NEAR(r["volume"].get<double>(), volume, kRelTol * volume);
  EXPECT_NEAR(r["bounding_radius"].get<double>(), kCubeDiameter / 2, kRelTol * kCubeDiameter);
  // Per unit density a cube's moments are all s^5 / 6.
  const double moment = std::pow(kSide, 5) / 6;
  expect_vec(r["principal_moments"], moment, moment, moment, kRelTol * moment, "moments");
  EXPECT_EQ(r["vertex_count"].get<double>(), 8);
  EXPECT_EQ(r["face_count"].get<double>(), 6);
  EXPECT_EQ(r["triangle_count"].get<double>(), 12);
  EXPECT_EQ(r["edge_count"].get<double>(), 12);
  ASSERT_EQ(r["vertices"].size(), 8u);
  ASSERT_EQ(r["faces"].size(), 6u);
  for (const Json& v : r["vertices"]) {
    for (int i = 0; i < 3; ++i)
      EXPECT_NEAR(std::abs(v[i].get<double>()), kSide / 2, kRelTol * kSide);
  }
  for (const Json& face : r["faces"]) {
    EXPECT_NEAR(face["offset"].get<double>(), kSide / 2, kRelTol * kSide);
    EXPECT_EQ(face["loop"].size(), 4u);
  }
}

// ---- No arguments, help

// `talus run` with no scene: the built-in scene (paper §3.3), here cut to 2 ms (50 steps), in a
// directory of its own: the scene file it ran, its outputs, the bed height beside the paper's.
TEST(TalusBuiltinScene, RunWithoutSceneRunsThePackingAndReportsTheBedHeight) {
  const std::string dir = talus_test::fresh_test_directory("cli", "builtin");
  const ProcessResult run = run_talus({"run", "--end", "0.002", "--output", dir});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  Json r = parse_or_fail(run.out);
  EXPECT_EQ(r["particles"].get<double>(), 63);
  EXPECT_EQ(r["steps"].get<double>(), 50);  // 2 ms at the scene's time step of 40 us
  EXPECT_EQ(r["paper_bed_height"].get<double>(), 0.16);
  // At 2 ms the particles still sit where the random fill put them, bounding spheres inside the
  // fill region (0 to 0.6 m): the highest vertex lies between the particles' size and the top.
  EXPECT_GT(r["bed_height"].get<double>(), 0.03);
  EXPECT_LE(r["bed_height"].get<double>(), 0.6);
  EXPECT_TRUE(std::filesystem::exists(dir + "/scene.yaml"));
  EXPECT_TRUE(std::filesystem::exists(dir + "/frames/run.json"));
  EXPECT_TRUE(std::filesystem::exists(dir + "/probes.csv"));
  EXPECT_NE(run.err.find("running the built-in scene"), std::string::npos) << run.err;
  EXPECT_NE(run.err.find("final bed height"), std::string::npos) << run.err;
  EXPECT_NE(run.err.find("reports about 16 cm"), std::string::npos) << run.err;
#if TALUS_HAVE_OPENCV
  EXPECT_TRUE(std::filesystem::exists(r["picture"].get<std::string>()))
      << r["picture"].get<std::string>();
  EXPECT_TRUE(std::filesystem::exists(dir + "/frames/render/render.json"));
#else
  EXPECT_NE(r["picture"].get<std::string>().find("without OpenCV"), std::string::npos);
#endif
}

// A run directory that is not one: exit 2 and one line naming it (or, without OpenCV, saying
// that render is not built in).
TEST(TalusRender, MissingDirectoryIsNamed) {
  const ProcessResult run = run_talus({"render", "/nonexistent/talus-run"});
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_TRUE(run.out.empty());
#if TALUS_HAVE_OPENCV
  EXPECT_NE(run.err.find("/nonexistent/talus-run: no such directory"), std::string::npos)
      << run.err;
#else
  EXPECT_NE(run.err.find("built without OpenCV"), std::string::npos) << run.err;
#endif
}

TEST(TalusHelp, HelpPrintsUsageAndSucceeds) {
  for (const char* flag : {"--help", "help", "-h"}) {
    const ProcessResult run = run_talus({flag});
    EXPECT_EQ(run.exit_code, 0) << flag;
    EXPECT_NE(run.out.find("usage:"), std::string::npos) << flag << "\n" << run.out;
    EXPECT_NE(run.out.find("talus overlap A POSE_A B POSE_B"), std::string::npos) << flag;
    EXPECT_TRUE(run.err.empty()) << flag;
  }
}

// Each command's help (generated by CLI11 from the options the parser knows) lists its options;
// `talus help COMMAND` is `talus COMMAND --help`.
TEST(TalusHelp, EachCommandListsItsOptions) {
  const std::pair<const char*, const char*> commands[] = {{"run", "--allow-unstable-step"},
                                                          {"render", "--max-speed"},
                                                          {"overlap", "overlap prints:"},
                                                          {"shape", "cylinder:D,L[,N]"}};
  for (const auto& [command, option] : commands) {
    for (const std::vector<std::string>& args :
         {std::vector<std::string>{command, "--help"}, std::vector<std::string>{"help", command}}) {
      const ProcessResult run = run_talus(args);
      EXPECT_EQ(run.exit_code, 0) << args[0] << " " << args[1];
      EXPECT_NE(run.out.find(option), std::string::npos) << args[0] << " " << args[1] << "\n"
                                                         << run.out;
      EXPECT_TRUE(run.err.empty()) << run.err;
    }
  }
}

// ---- Bad arguments: exit 2, nothing on stdout, one error line naming the argument, then usage

struct BadCase {
  std::vector<std::string> args;
  std::string names;  // text the error line must contain
};

TEST(TalusErrors, EachBadArgumentClassExitsTwoNamingTheArgument) {
  const std::string& id = kAtOrigin;
  const std::vector<BadCase> cases = {
      {{"frob"}, "unknown command 'frob'"},
      {{"overlap", kCube, id, kCube}, "overlap expects 4 arguments"},
      {{"overlap", kCube, id, kCube, id, id}, "got 5"},
      {{"shape"}, "shape expects 1 argument"},
      {{"overlap", kCube, "1,2,3", kCube, id}, "POSE_A '1,2,3'"},
      {{"overlap", kCube, id, kCube, "0,0,0,1,0,0,"}, "POSE_B"},
      {{"overlap", kCube, id, kCube, "0,0,0,1,0,0,x"}, "field qz 'x'"},
      {{"overlap", kCube, id, kCube, "0,0,0,1,0,0,nan"}, "field qz 'nan'"},
      {{"overlap", kCube, id, kCube, "0.1,0,0,0,0,0,0"}, "POSE_B '0.1,0,0,0,0,0,0'"},
      {{"overlap", "blob:1", id, kCube, id}, "A 'blob:1'"},
      {{"overlap", kCube, id, "cube:-1", id}, "B 'cube:-1'"},
      {{"shape", "cube:abc"}, "A 'cube:abc'"},
      {{"shape", "/nonexistent/particle.obj"}, "A '/nonexistent/particle.obj'"},
      {{"overlap", "cylinder:0.01,0.01,200", id, "cylinder:0.01,0.01,200", id}, "at most 256"},
      {{"run", "--end", "-1"}, "--end '-1': expected a positive time"},
      {{"render"}, "render expects a run directory"},
      {{"render", "a", "b"}, "'a' and 'b'"},
      {{"render", "d", "--view", "w"}, "--view 'w': expected one of x, -x, y, -y, z, -z"},
      {{"render", "d", "--color=red"}, "--color 'red': expected one of normal, velocity, id"},
      {{"render", "d", "--width", "0"}, "--width '0': expected a whole number"},
      {{"render", "d", "--every", "x"}, "--every 'x'"},
      {{"render", "d", "--fit", "walls"}, "--fit 'walls'"},
      {{"render", "d", "--max-speed", "-3"}, "--max-speed '-3'"},
      {{"render", "d", "--height", "20"}, "more than 32 px"},
      {{"render", "--fast", "d"}, "unknown option '--fast' for render"},
      {{"run", "a.yaml", "b.yaml"}, "'a.yaml' and 'b.yaml'"},
      {{"run", "--fast", "a.yaml"}, "unknown option '--fast'"},
      {{"run", "--solver", "exact", "a.yaml"}, "--solver 'exact': expected one of production"},
      {{"run", "--backend=gpu", "a.yaml"}, "--backend 'gpu': expected one of auto, cpu, cuda"},
      {{"run", "--precision", "half", "a.yaml"}, "--precision 'half'"},
      {{"run", "a.yaml", "--output"}, "--output expects a value"},
      {{"run", "--threads", "0", "a.yaml"},
       "--threads '0': expected a whole number from 1 to 1024"},
      {{"run", "--threads=-2", "a.yaml"}, "--threads '-2': expected a whole number"},
      {{"run", "--threads", "two", "a.yaml"}, "--threads 'two': expected a whole number"},
      {{"run", "--threads", "2.5", "a.yaml"}, "--threads '2.5': expected a whole number"},
      {{"run", "--threads", "99999999999", "a.yaml"},
       "--threads '99999999999': expected a whole number from 1 to 1024; it is too large"},
      {{"run", "--threads", "2000000000", "a.yaml"}, "from 1 to 1024; it is too large"},
      {{"-x", "run"}, "unknown option '-x' before the command"},
      {{"run", "a.yaml", "--threads"}, "--threads expects a value"},
      {{"run", "--resume", "d", "a.yaml"}, "drop the scene file 'a.yaml'"},
      {{"run", "--resume", "d", "--precision", "float"}, "drop --precision"},
      {{"help", "frob"}, "help 'frob'"},
  };
  for (const BadCase& c : cases) {
    std::string joined;
    for (const std::string& a : c.args) joined += a + " ";
    const ProcessResult run = run_talus(c.args);
    EXPECT_EQ(run.exit_code, 2) << joined;
    EXPECT_TRUE(run.out.empty()) << joined << "\n" << run.out;
    const std::string first_line = run.err.substr(0, run.err.find('\n'));
    EXPECT_EQ(first_line.rfind("talus: error: ", 0), 0u) << joined << "\n" << run.err;
    EXPECT_NE(first_line.find(c.names), std::string::npos) << joined << "\n" << run.err;
    EXPECT_NE(run.err.find("usage:"), std::string::npos) << joined;
  }
}

// Bytes that are not UTF-8 and control bytes in an argument are shown escaped, and a long one
// cut: the error line stays printable, one line and short (the bad-input table cannot write raw
// bytes into its arguments: its YAML strings are UTF-8).
TEST(TalusErrors, ArgumentsAreShownEscapedAndCut) {
  const ProcessResult raw = run_talus({"run", "--solver", "ab\xff\xfe\x1b[0m\n"});
  EXPECT_EQ(raw.exit_code, 2);
  EXPECT_NE(raw.err.find("--solver 'ab\\xff\\xfe\\x1b[0m\\n': expected one of production"),
            std::string::npos)
      << raw.err;
  const ProcessResult path = run_talus({"run", "--quiet", std::string(300, '\xe9') + ".yaml"});
  EXPECT_EQ(path.exit_code, 2);
  EXPECT_NE(path.err.find("\\xe9\\xe9\\xe9"), std::string::npos) << path.err;
  EXPECT_NE(path.err.find(" bytes in all ...]"), std::string::npos) << path.err;
  const std::string first_line = path.err.substr(0, path.err.find('\n'));
  EXPECT_LT(first_line.size(), 600u) << path.err;
  for (const char c : path.err)
    EXPECT_TRUE(c == '\n' || (static_cast<unsigned char>(c) >= 0x20 && c != 0x7f)) << path.err;
}

// A scene file that cannot be loaded: exit 2, the loader's message with file:line:column and key,
// no usage text (the arguments were fine).
TEST(TalusRun, BadSceneFileNamesFileLineAndKey) {
  char path[] = "/tmp/talus_cli_scene_XXXXXX.yaml";
  const int fd = mkstemps(path, 5);
  ASSERT_GE(fd, 0);
  const std::string text = "time: {step: 1.0e-4, end: 1}\nmaterials:\n  glass: {density: abc}\n";
  ASSERT_EQ(write(fd, text.data(), text.size()), static_cast<ssize_t>(text.size()));
  close(fd);
  const ProcessResult run = run_talus({"run", "--solver", "reference", path});
  unlink(path);
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_TRUE(run.out.empty()) << run.out;
  EXPECT_NE(run.err.find(std::string(path) + ":3:"), std::string::npos) << run.err;
  EXPECT_NE(run.err.find("materials.glass.density"), std::string::npos) << run.err;
  EXPECT_EQ(run.err.find("usage:"), std::string::npos) << run.err;
}

}  // namespace
