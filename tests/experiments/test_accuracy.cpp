// The accuracy-against-time study (experiments/accuracy/): its quick size on the host, the impact
// and the packing, and what its rows must say for the study to be believed.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>

#include "experiments/accuracy/accuracy.hpp"

namespace talus::accuracy {
namespace {

StudyOptions quick_options(const std::string& name) {
  StudyOptions options;
  options.quick = true;
  options.quiet = true;
  options.output_directory = std::string(TALUS_BINARY_DIR) + "/test-accuracy-" + name;
  std::filesystem::remove_all(options.output_directory);
  options.backend = "cpu";
  options.make_step = [](const Scene& scene) { return make_host_step(scene, 1); };
  options.commit = "test";
  options.machine = "test host";
  options.command = "test_accuracy";
  options.date = "2026-01-01T00:00:00Z";
  return options;
}

const Row& row_of(const StudyResult& result, const std::string& scene, const std::string& knob,
                  const std::string& setting) {
  for (const Row& r : result.rows)
    if (r.scene == scene && r.knob == knob && r.setting == setting) return r;
  throw std::runtime_error("no row " + scene + "/" + knob + "/" + setting);
}

TEST(AccuracyStudy, QuickImpactAndPacking) {
  StudyOptions options = quick_options("quick");
  options.scenes = {"impact", "packing"};
  const StudyResult result = run_study(options);

  // The paper's law at the advised step against Eqs. 27-28: within the 5 % that the validation
  // case allows from 10 to 60 degrees (validation/cylinder_wall_impact/expected.yaml).
  const Row& paper = row_of(result, "impact", "contact_law", "volume_paper");
  EXPECT_LT(paper.error, 0.05);
  EXPECT_GT(paper.steps, 100);  // the impact was resolved, not over in a step or two
  // Halving the step changes a converged impact by far less than its error (1e-3 relative).
  const Row& half = row_of(result, "impact", "time_step", "dt/2");
  EXPECT_NEAR(half.error, paper.error, 1e-3 * paper.error + 1e-6);
  EXPECT_GT(half.steps, paper.steps);
  // A finer prism is closer to the smooth cylinder: 20 sides beat 8.
  EXPECT_LT(row_of(result, "impact", "shape_resolution", "prism 20").error,
            row_of(result, "impact", "shape_resolution", "prism 8").error);
  // A sphere's contact force passes through its centre: no spin at all, a relative error of 1.
  EXPECT_EQ(row_of(result, "impact", "shape_resolution", "sphere (linear law)").error, 1.0);
  // The skin changes the work, never the result: identical on the host, which is deterministic.
  for (const char* scene : {"impact", "packing"}) {
    EXPECT_EQ(row_of(result, scene, "skin", "skin 0").error, 0.0) << scene;
    EXPECT_EQ(row_of(result, scene, "skin", "skin 1").error, 0.0) << scene;
  }
  // Single precision moves the impact's error by less than a percent of the speed scale.
  EXPECT_NEAR(row_of(result, "impact", "precision", "float").error, paper.error, 0.01);

  // The packing: its reference (the finest step) is listed without an error; the advised step's
  // bed is within 2 % of it (16 particles in a 10 cm tube: a bed of about one layer).
  EXPECT_TRUE(std::isnan(row_of(result, "packing", "time_step", "dt/2").error));
  EXPECT_LT(row_of(result, "packing", "time_step", "dt").error, 0.02);
  for (const Row& r : result.rows) {
    EXPECT_GT(r.wall_seconds, 0) << r.scene << " " << r.knob << " " << r.setting;
    EXPECT_GT(r.simulated_seconds, 0) << r.scene << " " << r.knob << " " << r.setting;
    EXPECT_GT(r.particles, 0u);
  }
  ASSERT_EQ(result.noise.size(), 2u);
  EXPECT_TRUE(std::isnan(result.noise[0].second));  // the impact has no seed
  EXPECT_GE(result.noise[1].second, 0);

  // The CSV as written: the provenance lines, the header, one line per row.
  std::ifstream file(result.csv_file);
  std::stringstream text;
  text << file.rdbuf();
  const std::string csv = text.str();
  EXPECT_NE(csv.find("# machine: test host\n"), std::string::npos);
  EXPECT_NE(csv.find("# commit: test\n"), std::string::npos);
  const std::string header =
      "knob,setting,value,scene,metric,reference,error,wall_seconds,simulated_seconds,steps,"
      "particles,precision\n";
  const std::size_t at = csv.find(header);
  ASSERT_NE(at, std::string::npos);
  std::size_t lines = 0;
  for (std::size_t k = at + header.size(); k < csv.size(); ++k) lines += csv[k] == '\n';
  EXPECT_EQ(lines, result.rows.size());
}

TEST(AccuracyStudy, RefusesUnknownNamesBeforeRunning) {
  StudyOptions options = quick_options("unknown");
  options.knobs = {"precision", "colour"};
  try {
    run_study(options);
    FAIL() << "an unknown knob ran";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("unknown knob 'colour'; expected one of contact_law"),
              std::string::npos)
        << error.what();
  }
  EXPECT_FALSE(std::filesystem::exists(options.output_directory));
  options.knobs = {};
  options.scenes = {"hopper"};
  EXPECT_THROW(run_study(options), std::invalid_argument);
}

}  // namespace
}  // namespace talus::accuracy
