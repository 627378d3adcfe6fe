// The probe file: columns from the scene, header, rows flushed as they are written and read back
// exactly, and errors naming the path.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "solver/io/probes.hpp"
#include "solver/scene/scene_loader.hpp"
#include "tests/support/test_files.hpp"

namespace talus {
namespace {

namespace fs = std::filesystem;

std::string test_directory(const std::string& name) {
  return talus_test::fresh_test_directory("test-io", name);
}
using talus_test::read_text;

TEST(Probes, ColumnsFollowTheSceneAndItsWalls) {
  const Scene scene = parse_scene(R"(time: {step: 1.0e-5, end: 0.1}
materials:
  steel: {density: 7800, youngs_modulus: 2.0e8, poisson_ratio: 0.3, friction: 0.3, restitution: 0.9}
templates:
  ball: {sphere: 0.004, material: steel}
particles:
  - explicit: [{template: ball, position: [0, 0, 0.05]}]
walls:
  - drum: {name: drum, center: [0, 0, 0.05], radius: 0.1, length: 0.1, material: steel}
  - plane: {point: [0, 0, 0], normal: [0, 0, 1], size: 1, material: steel}
effects:
  gravity: [0, 0, -9.81]
  contact: volume
outputs:
  probes:
    every: 10
    quantities: [bed_height, wall_forces, kinetic_energy, contact_count]
)",
                                  "probes.yaml", ".");
  const std::vector<std::string> columns = probe_columns(*scene.outputs.probes, scene.walls);
  const std::vector<std::string> expected = {
      "bed_height",      "wall_drum_fx",    "wall_drum_fy",    "wall_drum_fz",    "wall_drum_tx",
      "wall_drum_ty",    "wall_drum_tz",    "wall_plane_1_fx", "wall_plane_1_fy", "wall_plane_1_fz",
      "wall_plane_1_tx", "wall_plane_1_ty", "wall_plane_1_tz", "kinetic_energy",  "contact_count"};
  EXPECT_EQ(columns, expected);
}

TEST(Probes, RowsAreFlushedAsWrittenAndReadBackExactly) {
  const std::string dir = test_directory("probes");
  const std::string path = dir + "/out/probes.csv";  // its directory is made
  const std::vector<double> first = {0.1, 1.0 / 3, 42}, second = {-2.5e-300, 0, 7};
  {
    ProbeWriter writer(path, {"kinetic_energy", "bed_height", "contact_count"});
    EXPECT_EQ(read_text(path), "time,step,kinetic_energy,bed_height,contact_count\n");
    writer.write_row(1e-5 * 3, 3, first);
    // Before the writer is gone, the row is in the file: a run killed now keeps it.
    EXPECT_EQ(read_text(path),
              "time,step,kinetic_energy,bed_height,contact_count\n"
              "3.0000000000000004e-05,3,0.10000000000000001,0.33333333333333331,42\n");
    writer.write_row(6e-5, 6, second);
    EXPECT_THROW(writer.write_row(9e-5, 9, {1, 2}), std::invalid_argument);
  }
  const ProbeTable table = read_probe_file(path);
  EXPECT_EQ(table.header, (std::vector<std::string>{"time", "step", "kinetic_energy", "bed_height",
                                                    "contact_count"}));
  ASSERT_EQ(table.rows.size(), 2u);
  EXPECT_EQ(table.rows[0][0], 1e-5 * 3);
  EXPECT_EQ(table.rows[0][1], 3);
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(table.rows[0][k + 2], first[k]);  // %.17g reads back to the same double
    EXPECT_EQ(table.rows[1][k + 2], second[k]);
  }
}

TEST(Probes, AnUnwritablePathIsNamed) {
  const std::string dir = test_directory("probe_errors");
  std::ofstream(dir + "/file") << "x";
  try {
    ProbeWriter writer(dir + "/file/probes.csv", {"kinetic_energy"});
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("'" + dir + "/file'"), std::string::npos) << e.what();
  }
  fs::create_directories(dir + "/taken.csv");  // a directory where the file should go
  try {
    ProbeWriter writer(dir + "/taken.csv", {"kinetic_energy"});
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()),
              "cannot write probe file '" + dir + "/taken.csv': " + std::strerror(EISDIR));
  }
}

}  // namespace
}  // namespace talus
