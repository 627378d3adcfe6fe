// The output schedule both runners use (solver/io/output_schedule.hpp): which outputs are due at a
// step, the particles' rows gathered at most once a step however many outputs take them, and the
// ParaView series' state through a checkpoint.
#include "solver/io/output_schedule.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "solver/io/output_files.hpp"
#include "solver/scene/scene_loader.hpp"
#include "tests/support/test_files.hpp"

namespace talus {
namespace {

// Two particles at rest; counts how often the schedule asks for rows and probe values.
class CountingSource : public OutputSource {
 public:
  double time() const override { return 0.5; }
  std::vector<TrajectoryRow> rows() const override {
    ++row_calls;
    std::vector<TrajectoryRow> rows(2);
    rows[1].id = 1;
    rows[1].position = Vec3d(0.01, 0, 0);
    return rows;
  }
  std::vector<double> probe_values() const override {
    ++probe_calls;
    return {0.0};
  }
  mutable int row_calls = 0, probe_calls = 0;
};

Scene scene_with_outputs(const std::string& dir) {
  const std::string yaml =
      "time: {step: 1.0e-4, end: 1}\n"
      "materials:\n  m: {density: 1000, youngs_modulus: 1e6, poisson_ratio: 0.3, friction: 0,"
      " restitution: 0.5}\n"
      "templates:\n  g: {shape: \"cube:0.01\", material: m}\n"
      "particles:\n  - explicit:\n      - {template: g, position: [0, 0, 0]}\n"
      "      - {template: g, position: [0.01, 0, 0]}\n"
      "outputs:\n"
      "  trajectories: {every: 2, directory: " +
      dir +
      "/frames}\n"
      "  vtk: {every: 3, directory: " +
      dir +
      "/vtk}\n"
      "  probes: {every: 4, file: " +
      dir + "/probes.csv, quantities: [kinetic_energy]}\n";
  return parse_scene(yaml, "test.yaml", ".");
}

TEST(OutputSchedule, DueOutputsShareOneGatheringOfRows) {
  const std::string dir = talus_test::fresh_test_directory("test-io", "schedule");
  const Scene scene = scene_with_outputs(dir);
  OutputSchedule schedule(scene, "", "talus", 2);
  EXPECT_EQ(schedule.paths(),
            (std::vector<std::string>{dir + "/frames", dir + "/probes.csv", dir + "/vtk"}));
  EXPECT_FALSE(schedule.due(1, false));
  EXPECT_TRUE(schedule.due(1, true));  // the last step writes everything
  const struct {
    long long step;
    bool last;
    int rows, probes;  // calls expected at this step
  } steps[] = {{1, false, 0, 0}, {2, false, 1, 0},  {3, false, 1, 0}, {4, false, 1, 1},
               {6, false, 1, 0}, {12, false, 1, 1}, {13, true, 1, 1}};
  for (const auto& s : steps) {
    CountingSource source;
    schedule.write(s.step, s.last, source);
    EXPECT_EQ(source.row_calls, s.rows) << "step " << s.step;
    EXPECT_EQ(source.probe_calls, s.probes) << "step " << s.step;
  }
  for (const long long step : {2, 4, 6, 12, 13})
    EXPECT_TRUE(
        std::filesystem::exists(dir + "/frames/" + numbered_file_name("trajectory_", step, ".csv")))
        << step;
  EXPECT_FALSE(std::filesystem::exists(dir + "/frames/trajectory_000000003.csv"));
  EXPECT_TRUE(std::filesystem::exists(dir + "/vtk/particles_000000003.vtp"));
  EXPECT_TRUE(std::filesystem::exists(dir + "/frames/run.json"));
}

// A schedule restored from a checkpoint goes on with the ParaView collection of the one saved.
TEST(OutputSchedule, VtkSeriesContinuesThroughACheckpoint) {
  const std::string dir = talus_test::fresh_test_directory("test-io", "schedule_restart");
  const Scene scene = scene_with_outputs(dir);
  Checkpoint checkpoint;
  {
    OutputSchedule schedule(scene, "", "talus", 2);
    CountingSource source;
    schedule.write(3, false, source);
    schedule.save(checkpoint);
  }
  checkpoint.put_value("step.steps", 4LL);
  OutputSchedule resumed(scene, "", "talus", 2, &checkpoint);
  CountingSource source;
  resumed.write(6, false, source);
  const std::string pvd = talus_test::read_text(dir + "/vtk/particles.pvd");
  EXPECT_NE(pvd.find("particles_000000003.vtp"), std::string::npos) << pvd;
  EXPECT_NE(pvd.find("particles_000000006.vtp"), std::string::npos) << pvd;
}

// The trajectory format: as the scene names it, else HDF5 from kHdf5TrajectoryParticles particles
// on (those at the start and all that the feeds insert by the end); run.json says which.
TEST(OutputSchedule, TrajectoryFormatFollowsTheSceneOrTheRunsSize) {
  const std::string dir = talus_test::fresh_test_directory("test-io", "schedule_format");
  struct Case {
    std::string name, format, feed;
    std::size_t particles;
    const char* expected;
  };
  const std::string feed =
      "  - feed: {template: g, region: {box: {min: [0, 0, 0], max: [1, 1, 1]}}, rate: ";
  const Case cases[] = {{"small", "", "", 2, "csv"},
                        {"named", ", format: hdf5", "", 2, "hdf5"},
                        {"named_csv", ", format: csv", "", 20000, "csv"},
                        {"large", "", "", kHdf5TrajectoryParticles, "hdf5"},
                        {"fed", "", feed + "9998}\n", 2, "hdf5"},
                        {"fed_less", "", feed + "9997}\n", 2, "csv"}};
  for (const Case& c : cases) {
    const std::string out = dir + "/" + c.name;
    const std::string yaml =
        "time: {step: 1.0e-4, end: 1}\n"
        "materials:\n  m: {density: 1000, youngs_modulus: 1e6, poisson_ratio: 0.3, friction: 0,"
        " restitution: 0.5}\n"
        "templates:\n  g: {shape: \"cube:0.01\", material: m}\n"
        "particles:\n  - explicit:\n      - {template: g, position: [0, 0, 0]}\n" +
        c.feed + "outputs:\n  trajectories: {every: 1, directory: " + out + c.format + "}\n";
    const Scene scene = parse_scene(yaml, "test.yaml", ".");
    OutputSchedule schedule(scene, "", "talus", c.particles);
    CountingSource source;
    schedule.write(0, false, source);
    EXPECT_EQ(read_run_info(out).trajectory_format, c.expected) << c.name;
    const std::string frame =
        out + "/trajectory_000000000." + (std::string(c.expected) == "hdf5" ? "h5" : "csv");
    EXPECT_TRUE(std::filesystem::exists(frame)) << c.name;
    ASSERT_EQ(read_trajectory(out).size(), 1u) << c.name;
    EXPECT_EQ(read_trajectory(out)[0].rows.size(), 2u) << c.name;
  }
}

}  // namespace
}  // namespace talus
