// What a resumed step checks of a checkpoint's values before it uses them (check_state_fits in
// solver/step/step_state.hpp, called by HostStep::import_state and the CUDA step's): a real
// checkpoint of the restart scene (tests/step/restart_scene.hpp) after 60 steps, one section
// altered, written and read back, and the refusal's message: the file, the section, the value.
// A field left as written is accepted, so each refusal is that field's.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "solver/io/checkpoint.hpp"
#include "solver/step/host/host_step.hpp"
#include "tests/step/restart_scene.hpp"
#include "tests/step/step_test_util.hpp"
#include "tests/support/feed_scenes.hpp"

namespace talus {
namespace {

using talus_test::StepTempDir;

// The restart scene and the sections of its state after 60 steps (pair and wall contacts by then).
class CheckpointChecks : public ::testing::Test {
 protected:
  void SetUp() override {
    scene_ = talus_test::write_restart_scene(dir_.path());
    HostStep<double> step(scene_, 1);
    for (int k = 0; k < 60; ++k) step.step();
    written_ = step.export_state();
    ASSERT_GT(written_.pair_keys.size(), 1u) << "the scene should have pair contacts";
    ASSERT_GT(written_.wall_keys.size(), 0u) << "and wall contacts";
    put_step_state(checkpoint_, written_);
  }

  // The checkpoint, written to a file and read back, restored into a new step of the scene: the
  // refusal's message, or "" when it was accepted.
  std::string refusal(const Checkpoint& c) const {
    write_checkpoint(path(), c);
    HostStep<double> step(scene_, 1);
    try {
      step.import_state(get_step_state<double>(read_checkpoint(path())));
    } catch (const CheckpointError& e) {
      return e.what();
    }
    return "";
  }
  // The refusal of the checkpoint with section `name` replaced by `values`.
  template <class T>
  std::string refusal_with(const std::string& name, const std::vector<T>& values) const {
    Checkpoint c = checkpoint_;
    c.put(name, values);
    return refusal(c);
  }
  std::string path() const { return dir_.path() + "/crafted.bin"; }
  std::string section(const std::string& name) const {
    return path() + ": section '" + name + "': ";
  }
  template <class T>
  std::vector<T> values(const std::string& name) const {
    return checkpoint_.get<T>(name);
  }

  StepTempDir dir_;
  Scene scene_;
  StepState<double> written_;
  Checkpoint checkpoint_;
};

TEST_F(CheckpointChecks, WrittenCheckpointIsAccepted) {
  EXPECT_EQ(refusal(checkpoint_), "");
}

// The crash the checkpoint fuzzer found (tests/fuzz/fuzz_checkpoint.cpp): a material id beyond
// the scene's indexed the contact law's tables past their end in the next step.
TEST_F(CheckpointChecks, MaterialIdOutOfRange) {
  std::vector<int> m = values<int>("particles.material_id");
  m[2] = 7;
  EXPECT_EQ(refusal_with("particles.material_id", m),
            section("particles.material_id") + "particle 2 (global id " +
                std::to_string(written_.global_ids[2]) +
                ") has material id 7; the scene has 1 materials");
  m[2] = -1;
  EXPECT_NE(refusal_with("particles.material_id", m).find("has material id -1"), std::string::npos);
}

TEST_F(CheckpointChecks, TemplateIdOutOfRange) {
  const std::string id = std::to_string(written_.global_ids[0]);
  EXPECT_EQ(refusal_with("particles.template_id", std::vector<int>(written_.count, 1)),
            section("particles.template_id") + "particle 0 (global id " + id +
                ") has template id 1; the scene has 1 templates");
}

TEST_F(CheckpointChecks, StepCountAndTime) {
  EXPECT_EQ(refusal_with("step.steps", std::vector<long long>{-5}),
            section("step.steps") + "expected a step count >= 0, got -5");
  // 60 steps of 2e-5 s: 1.2e-3 s; 1 s is no sum of them, nor is NaN.
  EXPECT_NE(refusal_with("step.time", std::vector<double>{1.0})
                .find(section("step.time") + "1 s after 60 steps of 2.0000000000000002e-05 s; "
                                             "expected 0.0012"),
            std::string::npos);
  EXPECT_NE(refusal_with("step.time", std::vector<double>{std::nan("")})
                .find(section("step.time") + "nan s after 60 steps"),
            std::string::npos);
  // The written time is the steps' running sum, not 60 * dt: within the round-off it is accepted.
  const double t = checkpoint_.get_value<double>("step.time");
  EXPECT_EQ(refusal_with("step.time", std::vector<double>{std::nextafter(t, 1.0)}), "");
}

TEST_F(CheckpointChecks, GlobalIds) {
  std::vector<long long> ids = values<long long>("particles.global_id");
  const std::vector<long long> next = values<long long>("step.ids");
  ASSERT_EQ(next.size(), 2u);
  std::vector<long long> twin = ids;
  twin[3] = twin[4];
  EXPECT_EQ(refusal_with("particles.global_id", twin), section("particles.global_id") +
                                                           "global id " + std::to_string(ids[4]) +
                                                           " is held by two particles");
  std::vector<long long> beyond = ids;
  beyond[1] = next[0];
  EXPECT_EQ(refusal_with("particles.global_id", beyond),
            section("particles.global_id") + "particle 1 (global id " + std::to_string(next[0]) +
                "): expected an id from 0 to " + std::to_string(next[0] - 1) + " (the next id is " +
                std::to_string(next[0]) + ")");
  std::vector<long long> negative = ids;
  negative[0] = -3;
  EXPECT_NE(refusal_with("particles.global_id", negative).find("(global id -3): expected an id"),
            std::string::npos);
  EXPECT_EQ(refusal_with("step.ids", std::vector<long long>{next[0], -1}),
            section("step.ids") + "removed -1 particles; expected >= 0");
  EXPECT_EQ(refusal_with("step.ids", std::vector<long long>{-2, 0}),
            section("step.ids") + "next id -2; expected >= 0");
}

TEST_F(CheckpointChecks, ParticleArraysFinite) {
  std::vector<double> x = values<double>("particles.position.x");
  x[5] = std::numeric_limits<double>::infinity();
  EXPECT_EQ(refusal_with("particles.position.x", x),
            section("particles.position.x") + "particle 5 (global id " +
                std::to_string(written_.global_ids[5]) + ") has inf");
  std::vector<double> f = values<double>("particles.force.z");
  f[0] = std::nan("");
  EXPECT_NE(refusal_with("particles.force.z", f).find("particle 0"), std::string::npos);
}

// The checkpoint fuzzer's second finding: a bounding radius of -1761 m passed as finite and
// stopped the next step's neighbour search with std::invalid_argument.
TEST_F(CheckpointChecks, BoundingRadiusOfTheTemplate) {
  std::vector<double> r = values<double>("particles.bounding_radius");
  const double written = r[3];
  EXPECT_EQ(written, scene_.templates[0].bounding_radius);  // 4.5 mm, in double exactly
  r[3] = -1761.28;
  EXPECT_EQ(refusal_with("particles.bounding_radius", r),
            section("particles.bounding_radius") + "particle 3 (global id " +
                std::to_string(written_.global_ids[3]) +
                ") has -1761.28 m; its template 'ico' has 0.0045000000000000005 m");
  r[3] = written * (1 + 1e-3);  // finite and positive, but not the template's
  EXPECT_NE(refusal_with("particles.bounding_radius", r).find("particle 3"), std::string::npos);
}

TEST_F(CheckpointChecks, OrientationOfUnitNorm) {
  std::vector<double> w = values<double>("particles.orientation.w");
  const std::vector<double> written_w = w;
  w[4] = 2;  // norm sqrt(4 + 1 - w^2) > 1.7
  const std::string message = refusal_with("particles.orientation.w", w);
  EXPECT_NE(message.find(section("particles.orientation.*") + "particle 4"), std::string::npos)
      << message;
  EXPECT_NE(message.find("expected 1 within 2.2204460492503131e-13"), std::string::npos) << message;
  // Every component scaled by 1 + 1e-14: a norm off by 1e-14, round-off, is accepted.
  Checkpoint scaled = checkpoint_;
  for (const char* part : {"w", "x", "y", "z"}) {
    std::vector<double> q = values<double>(std::string("particles.orientation.") + part);
    for (double& v : q) v *= 1 + 1e-14;
    scaled.put(std::string("particles.orientation.") + part, q);
  }
  EXPECT_EQ(refusal(scaled), "");
}

TEST_F(CheckpointChecks, PairHistoryKeys) {
  const std::vector<long long> keys = values<long long>("pairs.keys");  // low, high, low, ...
  const long long next = values<long long>("step.ids")[0];
  std::vector<long long> swapped = keys;  // the first two keys in the wrong order
  std::swap(swapped[0], swapped[2]);
  std::swap(swapped[1], swapped[3]);
  EXPECT_EQ(refusal_with("pairs.keys", swapped),
            section("pairs.keys") + "key 1 (" + std::to_string(keys[0]) + ", " +
                std::to_string(keys[1]) +
                "): the keys are not sorted in increasing order, each once");
  std::vector<long long> reversed = keys;  // high before low
  std::swap(reversed[0], reversed[1]);
  EXPECT_NE(
      refusal_with("pairs.keys", reversed)
          .find("expected a second particle id above the first and below " + std::to_string(next)),
      std::string::npos);
  std::vector<long long> unknown = keys;  // a particle that was never given an id
  unknown[unknown.size() - 1] = next + 4;
  EXPECT_NE(refusal_with("pairs.keys", unknown).find(section("pairs.keys")), std::string::npos);
}

TEST_F(CheckpointChecks, WallHistoryKeysAndHistories) {
  std::vector<long long> keys = values<long long>("walls.keys");
  keys[1] = 2;  // the scene has a drum and a lid
  EXPECT_EQ(refusal_with("walls.keys", keys), section("walls.keys") + "key 0 (" +
                                                  std::to_string(keys[0]) +
                                                  ", 2): wall 2, the scene has 2 walls");
  std::vector<double> h = values<double>("walls.histories");
  h[9 + 3] = std::nan("");  // the second history's approach speed
  EXPECT_EQ(refusal_with("walls.histories", h), section("walls.histories") + "history 1 has nan");
  std::vector<double> p = values<double>("pairs.histories");
  p[0] = -std::numeric_limits<double>::infinity();
  EXPECT_EQ(refusal_with("pairs.histories", p), section("pairs.histories") + "history 0 has -inf");
}

TEST_F(CheckpointChecks, ListReferenceAndEnergy) {
  // The CUDA step's list reference (absent from a host step's checkpoint): 3 numbers a particle.
  EXPECT_EQ(refusal_with("pairs.reference", std::vector<double>(5, 0.0)),
            section("pairs.reference") + "expected 3 values per particle");
  Checkpoint with_reference = checkpoint_;
  std::vector<double> reference(3 * written_.count, 0.0);
  reference[4] = std::nan("");
  with_reference.put("pairs.reference", reference);
  with_reference.put_value<std::uint8_t>("pairs.stale", 0);
  EXPECT_EQ(refusal(with_reference),
            section("pairs.reference") + "reference of particle 1 has nan");
  std::vector<double> e = values<double>("step.energy");
  e[2] = std::numeric_limits<double>::infinity();
  EXPECT_EQ(refusal_with("step.energy", e), section("step.energy") + "number 2 has inf");
}

TEST(CheckpointFeedStates, UnreadableFeedStateNamesTheSection) {
  StepTempDir dir;
  const Scene scene = talus_test::scene_from(
      std::string("time: {step: 5.0e-6, end: 0.03}\nmaterials:\n  glass: {density: 2500, "
                  "youngs_modulus: 1.0e7, poisson_ratio: 0.25, friction: 0.4, restitution: 0.5}") +
      testing::kBallFeedScene);
  HostStep<double> step(scene, 1);
  for (int k = 0; k < 10; ++k) step.step();
  Checkpoint c;
  put_step_state(c, step.export_state());
  c.put_text("feeds.states", "talus-feeder-v1 many\n");
  const std::string path = dir.path() + "/feed.bin";
  write_checkpoint(path, c);
  HostStep<double> back(scene, 1);
  try {
    back.import_state(get_step_state<double>(read_checkpoint(path)));
    ADD_FAILURE() << "expected the feed state to be refused";
  } catch (const CheckpointError& e) {
    EXPECT_EQ(std::string(e.what()).rfind(path + ": section 'feeds.states': feed 0: test.yaml:", 0),
              0u)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("got 'talus-feeder-v1 many'"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace talus
