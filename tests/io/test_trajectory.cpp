// Trajectory files and run.json: exact round trip, the header and columns, no temporary file
// left behind, and errors that name the path and the reason.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "solver/io/output_files.hpp"
#include "solver/io/trajectory.hpp"
#include "tests/support/json_test_util.hpp"
#include "tests/support/test_files.hpp"

namespace talus {
namespace {

namespace fs = std::filesystem;

std::string test_directory(const std::string& name) {
  return talus_test::fresh_test_directory("test-io", name);
}
using talus_test::file_names;
using talus_test::read_text;

// Doubles that a careless format would not read back: many digits, extremes, subnormals, -0.
std::vector<TrajectoryRow> awkward_rows(int count, unsigned seed) {
  std::mt19937_64 bits(seed);
  const double special[] = {0.1,
                            1.0 / 3,
                            -0.0,
                            std::numeric_limits<double>::max(),
                            std::numeric_limits<double>::min(),
                            std::numeric_limits<double>::denorm_min(),
                            -2.2250738585072009e-308,  // the largest subnormal, negative
                            1e23,
                            9007199254740993.0};
  std::vector<TrajectoryRow> rows;
  for (int i = 0; i < count; ++i) {
    double v[13];
    for (int k = 0; k < 13; ++k) {
      if ((i + k) % 4 == 0) {
        v[k] = special[(i * 13 + k) % 9];
      } else {
        std::uint64_t word;
        do word = bits();
        while (((word >> 52) & 0x7ff) == 0x7ff);  // any finite double, by its bits
        std::memcpy(&v[k], &word, sizeof word);
      }
    }
    TrajectoryRow row;
    row.id = 1000000007LL * i;
    row.template_index = i % 3;
    row.position = {v[0], v[1], v[2]};
    row.orientation = {v[3], v[4], v[5], v[6]};
    row.velocity = {v[7], v[8], v[9]};
    row.angular_velocity = {v[10], v[11], v[12]};
    rows.push_back(row);
  }
  return rows;
}

bool same_bits(const TrajectoryRow& a, const TrajectoryRow& b) {
  const auto numbers = [](const TrajectoryRow& r) {
    return std::vector<double>{r.position.x,        r.position.y,         r.position.z,
                               r.orientation.w,     r.orientation.x,      r.orientation.y,
                               r.orientation.z,     r.velocity.x,         r.velocity.y,
                               r.velocity.z,        r.angular_velocity.x, r.angular_velocity.y,
                               r.angular_velocity.z};
  };
  const std::vector<double> x = numbers(a), y = numbers(b);
  return a.id == b.id && a.template_index == b.template_index &&
         std::memcmp(x.data(), y.data(), x.size() * sizeof(double)) == 0;
}

TEST(Trajectory, RoundTripIsBitExact) {
  const std::string dir = test_directory("round_trip");
  const std::vector<TrajectoryRow> first = awkward_rows(500, 1), second = awkward_rows(300, 2);
  write_trajectory_frame(dir, 2000, second);  // written out of order: the reader sorts
  write_trajectory_frame(dir, 0, first);
  write_trajectory_frame(dir, 1000, {});
  const std::vector<TrajectoryFrame> frames = read_trajectory(dir);
  ASSERT_EQ(frames.size(), 3u);
  EXPECT_EQ(frames[0].step, 0);
  EXPECT_EQ(frames[1].step, 1000);
  EXPECT_EQ(frames[2].step, 2000);
  EXPECT_TRUE(frames[1].rows.empty());
  ASSERT_EQ(frames[0].rows.size(), first.size());
  ASSERT_EQ(frames[2].rows.size(), second.size());
  for (std::size_t i = 0; i < first.size(); ++i)
    EXPECT_TRUE(same_bits(frames[0].rows[i], first[i])) << "row " << i;
  for (std::size_t i = 0; i < second.size(); ++i)
    EXPECT_TRUE(same_bits(frames[2].rows[i], second[i])) << "row " << i;
  EXPECT_TRUE(std::signbit(frames[0].rows[0].position.z) ==
              std::signbit(first[0].position.z));  // -0 stays -0 (memcmp checked it too)
}

// HDF5 frames (trajectory_hdf5.cpp): ids, templates and positions read back to the bit, the
// orientation and velocities to the float each was rounded to (the format's choice: 76 bytes a
// particle), frames of both formats in one directory read in step order, no temporary file left.
TEST(Trajectory, Hdf5FramesReadBack) {
  const std::string dir = test_directory("hdf5");
  const std::vector<TrajectoryRow> rows = awkward_rows(400, 3);
  write_trajectory_frame_hdf5(dir, 7, 0.25, rows);
  write_trajectory_frame_hdf5(dir, 9, 0.5, {});
  write_trajectory_frame(dir, 8, awkward_rows(3, 4));
  const std::vector<TrajectoryFrame> frames = read_trajectory(dir);
  ASSERT_EQ(frames.size(), 3u);
  EXPECT_EQ(frames[0].step, 7);
  EXPECT_EQ(frames[1].step, 8);
  EXPECT_EQ(frames[2].step, 9);
  EXPECT_TRUE(frames[2].rows.empty());
  ASSERT_EQ(frames[0].rows.size(), rows.size());
  const auto as_float = [](double v) { return double(static_cast<float>(v)); };
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const TrajectoryRow& a = frames[0].rows[i];
    const TrajectoryRow& b = rows[i];
    EXPECT_EQ(a.id, b.id);
    EXPECT_EQ(a.template_index, b.template_index);
    EXPECT_EQ(std::memcmp(&a.position, &b.position, sizeof(Vec3d)), 0) << "row " << i;
    const double got[] = {a.orientation.w,     a.orientation.x,      a.orientation.y,
                          a.orientation.z,     a.velocity.x,         a.velocity.y,
                          a.velocity.z,        a.angular_velocity.x, a.angular_velocity.y,
                          a.angular_velocity.z};
    const double put[] = {b.orientation.w,     b.orientation.x,      b.orientation.y,
                          b.orientation.z,     b.velocity.x,         b.velocity.y,
                          b.velocity.z,        b.angular_velocity.x, b.angular_velocity.y,
                          b.angular_velocity.z};
    for (int k = 0; k < 10; ++k) {
      if (std::isfinite(put[k])) {
        EXPECT_EQ(got[k], as_float(put[k])) << "row " << i << " " << k;
      }
    }
  }
  EXPECT_EQ(file_names(dir),
            (std::vector<std::string>{"trajectory_000000007.h5", "trajectory_000000008.csv",
                                      "trajectory_000000009.h5"}));
  // A file that is not HDF5 under a frame's name is refused, naming it.
  write_file_atomically(dir + "/trajectory_000000010.h5", "id,template\n");
  try {
    read_trajectory(dir);
    ADD_FAILURE() << "read a text file as HDF5";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("trajectory_000000010.h5: cannot open the file as HDF5"),
              std::string::npos)
        << e.what();
  }
}

TEST(Trajectory, Hdf5FrameIntoAMissingDirectoryNamesThePath) {
  const std::string dir = test_directory("hdf5_missing") + "/missing";
  try {
    write_trajectory_frame_hdf5(dir, 3, 0.0, awkward_rows(2, 5));
    ADD_FAILURE() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("cannot write '" + dir + "/trajectory_000000003.h5'"),
              std::string::npos)
        << e.what();
  }
}

TEST(Trajectory, FileNameHeaderAndColumns) {
  const std::string dir = test_directory("columns");
  EXPECT_EQ(trajectory_file_name(1200), "trajectory_000001200.csv");
  EXPECT_EQ(trajectory_file_name(0), "trajectory_000000000.csv");
  EXPECT_EQ(trajectory_file_name(12345678901LL), "trajectory_12345678901.csv");
  TrajectoryRow row;
  row.id = 7;
  row.template_index = 2;
  row.position = {1, 2, 3};
  row.orientation = {0.5, -0.5, 0.5, -0.5};
  row.velocity = {0.1, 0, -9.81};
  row.angular_velocity = {0, 0, 10};
  write_trajectory_frame(dir, 1200, {row});
  // Every column in its place, each double printed with 17 significant digits.
  EXPECT_EQ(read_text(dir + "/trajectory_000001200.csv"),
            "id,template,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz\n"
            "7,2,1,2,3,0.5,-0.5,0.5,-0.5,0.10000000000000001,0,-9.8100000000000005,0,0,10\n");
  EXPECT_EQ(file_names(dir), std::vector<std::string>{"trajectory_000001200.csv"});
}

TEST(Trajectory, NoTemporaryFileIsLeftAndOtherFilesAreIgnored) {
  const std::string dir = test_directory("no_temporary");
  write_trajectory_frame(dir, 5, awkward_rows(10, 3));
  write_trajectory_frame(dir, 5, awkward_rows(20, 4));  // rewriting replaces the file
  write_run_info(dir, {"scene.yaml", "talus", "double", 1e-5, {"grain"}});
  EXPECT_EQ(file_names(dir), (std::vector<std::string>{"run.json", "trajectory_000000005.csv"}));
  // What an interrupted write leaves, a temporary file, is not read as a frame.
  std::ofstream(dir + "/trajectory_000000010.csv.tmp") << "id,template\n1,";
  const std::vector<TrajectoryFrame> frames = read_trajectory(dir);
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].rows.size(), 20u);
}

TEST(Trajectory, RunJsonRecordsTheRun) {
  const std::string dir = test_directory("run_json");
  RunInfo info;
  info.scene_file = "scenes/\"drum\".yaml";  // a quote to escape
  info.solver = "reference";
  info.precision = "float";
  info.time_step = 2.0e-6;
  info.templates = {"grain", "pebble", "ball"};
  write_run_info(dir, info);
  talus_test::Json json = talus_test::parse_or_fail(read_text(dir + "/run.json"));
  EXPECT_EQ(json["scene"].get<std::string>(), info.scene_file);
  EXPECT_EQ(json["solver"].get<std::string>(), "reference");
  EXPECT_EQ(json["precision"].get<std::string>(), "float");
  EXPECT_EQ(json["time_step"].get<double>(), 2.0e-6);  // the shortest text that reads back: exact
  ASSERT_EQ(json["templates"].size(), 3u);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(json["templates"][i]["id"].get<double>(), i);
    EXPECT_EQ(json["templates"][i]["name"].get<std::string>(), info.templates[i]);
  }
}

// run.json reads back what was written, \u escapes of any code point included (the regular
// expressions that read it before kept one byte of each), and a file that is not what talus
// writes is refused naming the file and the member.
TEST(Trajectory, RunJsonReadsBack) {
  const std::string dir = test_directory("run_json_read");
  RunInfo info;
  info.scene_file = "sc\u00e8nes/\"drum\" \xe4\xb8\xad.yaml";
  info.solver = "talus";
  info.precision = "double";
  info.time_step = 1.0 / 3.0 * 1e-5;
  info.templates = {"grain",
                    "\xc3\xa9"
                    "clat"};
  write_run_info(dir, info);
  const RunInfo back = read_run_info(dir);
  EXPECT_EQ(back.scene_file, info.scene_file);
  EXPECT_EQ(back.solver, info.solver);
  EXPECT_EQ(back.precision, info.precision);
  EXPECT_EQ(back.time_step, info.time_step);
  EXPECT_EQ(back.templates, info.templates);
  // The same file written by another tool, with escapes for the non-ASCII letters.
  write_file_atomically(dir + "/run.json",
                        "{\"templates\": [{\"id\": 0, \"name\": \"\\u00e9clat\"}], "
                        "\"time_step\": 2e-6, \"precision\": \"float\", \"solver\": "
                        "\"reference\", \"scene\": \"s\\u4e2d.yaml\"}");
  const RunInfo escaped = read_run_info(dir);
  EXPECT_EQ(escaped.templates, std::vector<std::string>{"\xc3\xa9"
                                                        "clat"});
  EXPECT_EQ(escaped.scene_file, "s\xe4\xb8\xad.yaml");
}

TEST(Trajectory, BadRunJsonNamesTheFileAndTheMember) {
  const std::string dir = test_directory("run_json_bad");
  const std::string good =
      "\"scene\": \"s.yaml\", \"solver\": \"talus\", \"precision\": \"double\"";
  const std::pair<std::string, std::string> cases[] = {
      {"{" + good + ", \"time_step\": 1e-5, \"templates\": [}", "not valid JSON"},
      {"[1, 2]", "expected an object"},
      {"{\"solver\": \"talus\"}", "\"scene\" (missing)"},
      {"{" + good + ", \"time_step\": -1, \"templates\": []}", "\"time_step\" (s), got -1"},
      {"{" + good + ", \"time_step\": \"1e-5\", \"templates\": []}", "positive number"},
      {"{" + good + ", \"time_step\": 1e-5}", "\"templates\" (missing)"},
      {"{" + good + ", \"time_step\": 1e-5, \"templates\": [{\"id\": 1, \"name\": \"g\"}]}",
       "templates[0].id = 0"},
      {"{\"scene\": 3}", "a string member \"scene\", got 3"}};
  for (const auto& [text, expected] : cases) {
    write_file_atomically(dir + "/run.json", text);
    try {
      read_run_info(dir);
      ADD_FAILURE() << "accepted: " << text;
    } catch (const std::runtime_error& e) {
      const std::string what = e.what();
      EXPECT_EQ(what.rfind(dir + "/run.json: ", 0), 0u) << what;
      EXPECT_NE(what.find(expected), std::string::npos) << what << "\n  expected: " << expected;
    }
  }
}

TEST(Trajectory, ErrorsNameThePathAndTheReason) {
  const std::string dir = test_directory("errors");
  // A directory that does not exist (even root cannot write into it).
  try {
    write_trajectory_frame(dir + "/missing", 3, {});
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(
        std::string(e.what()),
        "cannot write '" + dir + "/missing/trajectory_000000003.csv': " + std::strerror(ENOENT));
  }
  // An output directory where a file is: it cannot be created.
  std::ofstream(dir + "/file") << "x";
  try {
    create_output_directory(dir + "/file/out");
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(
        std::string(e.what()).rfind("cannot create output directory '" + dir + "/file/out': ", 0),
        0u)
        << e.what();
  }
  EXPECT_THROW(create_output_directory(dir + "/file"), std::runtime_error);
  create_output_directory(dir + "/a/b/c");  // parents are made
  EXPECT_TRUE(fs::is_directory(dir + "/a/b/c"));
  // A malformed frame names its line.
  std::ofstream(dir + "/trajectory_000000001.csv")
      << kTrajectoryHeader << "\n1,0,1,2,3,1,0,0,0,0,0,0,0,0,0\n2,0,1,2,x,1,0,0,0,0,0,0,0,0,0\n";
  try {
    read_trajectory_frame(dir + "/trajectory_000000001.csv");
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()),
              dir + "/trajectory_000000001.csv:3: expected a number, got 'x'");
  }
}

}  // namespace
}  // namespace talus
