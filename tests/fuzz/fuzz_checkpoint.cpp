// libFuzzer target: the checkpoint reader (solver/io/checkpoint.hpp) and the restore of what it
// read into a host step of a tiny scene (icosahedra on a floor with friction and rotation, a
// feed, a domain box: every section a checkpoint can hold), then two steps, so that
// crafted values reach the code that uses them. Before writing the input, its file-size field and
// checksum are set to fit its bytes: otherwise nearly every mutation would stop at the checksum
// (the size and checksum checks themselves are tested in tests/step/test_restart.cpp). A
// CheckpointError (or another std::runtime_error talus throws on purpose, or the neighbour
// search's std::invalid_argument for a position that a step made non-finite) is an answer; a crash,
// a sanitizer report, another exception or a hang is a bug.
//
// With TALUS_FUZZ_WRITE_SEEDS=DIR in the environment the target first writes checkpoints of the
// scene after 0, 40 and 400 steps into DIR (scripts/fuzz's seed corpus).
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <string>

#include "solver/io/checkpoint.hpp"
#include "solver/scene/scene_loader.hpp"
#include "solver/step/host/host_step.hpp"
#include "tests/fuzz/fuzz_input.hpp"

namespace {

// Four icosahedra dropped onto the floor of a box, touching one another, and a feed of smaller ones
// from t = 1 ms: pair and wall histories, a feed state and a domain box all in the checkpoint.
const char* const kScene = R"(time: {step: 2.0e-5, end: 0.02}
materials:
  glass: {density: 2500, youngs_modulus: 1.0e7, poisson_ratio: 0.25, friction: 0.4, restitution: 0.5}
templates: {ico: {shape: "icosahedron:0.009", material: glass},
            pebble: {shape: "icosahedron:0.005", material: glass}}
domain: {min: [-0.03, -0.03, -0.01], max: [0.03, 0.03, 0.05]}
walls: [box: {min: [-0.02, -0.02, 0], max: [0.02, 0.02, 0.04], material: glass}]
particles:
  - explicit:
      - {template: ico, position: [-0.0042, 0, 0.0045], velocity: [0.1, 0, -0.5]}
      - {template: ico, position: [0.0042, 0, 0.0045], velocity: [-0.1, 0, -0.5]}
      - {template: ico, position: [0, 0.0075, 0.0045], orientation: {axis: [0, 0, 1], degrees: 30}}
      - {template: ico, position: [0, -0.0075, 0.0045], angular_velocity: [0, 0, 20]}
  - feed: {template: pebble, rate: 2000, start: 0.001, stop: 0.01, velocity: [0, 0, -1],
           region: {box: {min: [-0.015, -0.015, 0.02], max: [0.015, 0.015, 0.035]}}}
effects: {gravity: [0, 0, -9.81], contact: volume, friction: true, rotation: true}
)";

const talus::Scene& scene() {
  static const talus::Scene s = talus::parse_scene(kScene, "fuzz_checkpoint.yaml", ".");
  return s;
}

void write_seeds(const std::string& directory) {
  std::filesystem::create_directories(directory);
  talus::HostStep<double> step(scene(), 1);
  int done = 0;
  for (const int steps : {0, 40, 400}) {
    for (; done < steps; ++done) step.step();
    talus::Checkpoint c;
    talus::put_step_state(c, step.export_state());
    talus::write_checkpoint(directory + "/step_" + std::to_string(steps) + ".bin", c);
  }
}

// The file-size field (bytes 16..23) and the trailing checksum made to fit `bytes`.
void fit_size_and_checksum(std::string& bytes) {
  constexpr std::size_t kHeader = 32, kChecksum = 8;
  if (bytes.size() < kHeader + kChecksum) return;
  const std::uint64_t size = bytes.size();
  std::memcpy(&bytes[16], &size, sizeof size);
  const std::size_t body = bytes.size() - kChecksum;
  const std::uint64_t sum = talus::fnv1a64(bytes.data(), body);
  std::memcpy(&bytes[body], &sum, sizeof sum);
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  if (const char* seeds = std::getenv("TALUS_FUZZ_WRITE_SEEDS")) write_seeds(seeds);
  scene();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::string bytes(reinterpret_cast<const char*>(data), size);
  fit_size_and_checksum(bytes);
  const std::string path = talus_fuzz::write_input(
      reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size(), "in.bin");
  try {
    const talus::Checkpoint checkpoint = talus::read_checkpoint(path);
    talus::HostStep<double> step(scene(), 1);
    step.import_state(talus::get_step_state<double>(checkpoint));
    step.step();
    step.step();
  } catch (const std::runtime_error&) {
  } catch (const std::invalid_argument&) {  // the neighbour search's refusal of a diverged state
  }
  return 0;
}
