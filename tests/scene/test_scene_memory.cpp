// The memory estimate (solver/scene/scene_memory.hpp): the particles a scene will create, counted
// from its requests before any is made, times kBytesPerParticle, against the memory available.
#include <unistd.h>

#include <fstream>

#include "solver/scene/scene_limits.hpp"
#include "solver/scene/scene_memory.hpp"
#include "tests/scene/scene_test_util.hpp"

namespace talus {
namespace {

const std::string kOneParticle = "      - {template: grain, position: [0, 0, 0.05]}\n";

Scene parse_with(const std::string& entries) {
  return parse_scene(replaced(kValidScene, kOneParticle, kOneParticle + entries), "errors.yaml",
                     scene_data_dir());
}

// 1 explicit + a 10 x 10 x 10 lattice + a fill of 50 + a feed of 400/s for 0.05 s (20): 1071.
const std::string kEntries =
    "  - lattice: {template: grain, region: {box: {min: [1, 0, 0], max: [1.12, 0.12, 0.12]}}, "
    "spacing: 0.012}\n"
    "  - random: {template: grain, region: {box: {min: [2, 0, 0], max: [2.2, 0.2, 0.2]}}, count: "
    "50}\n"
    "  - feed: {template: grain, region: {box: {min: [3, 0, 0], max: [3.1, 0.1, 0.1]}}, rate: "
    "400, start: 0.05}\n";

TEST(SceneMemory, CountsEveryEntryBeforeMakingAny) {
  const Scene scene = parse_with(kEntries);
  const MemoryEstimate e = estimate_scene_memory(scene);
  EXPECT_EQ(e.particles, 1 + 1000 + 50 + 20);
  EXPECT_EQ(e.bytes, 1071 * kBytesPerParticle);
  EXPECT_EQ(e.largest.key, "particles[1].lattice");
  EXPECT_EQ(e.largest_particles, 1000);
}

TEST(SceneMemory, RefusesAboveTheMemoryAvailableNamingCountBytesAndKey) {
  const Scene scene = parse_with(kEntries);
  const std::uint64_t needed = std::uint64_t(1071 * kBytesPerParticle);
  EXPECT_NO_THROW(check_scene_memory(scene, needed));  // exactly enough
  EXPECT_NO_THROW(check_scene_memory(scene, 0));       // unknown: never refused
  try {
    check_scene_memory(scene, needed - 1);
    ADD_FAILURE() << "no SceneError";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.line(), 17);  // the lattice, the largest entry
    EXPECT_EQ(e.key(), "particles[1].lattice");
    EXPECT_EQ(e.message(),
              "the scene would create 1071 particles (1000 of them from this entry), an "
              "estimated 2193408 bytes (2048 a particle), more than the 2193407 bytes of memory "
              "this machine has; ask for fewer particles");
  }
}

TEST(SceneMemory, ARandomFillOf1e8InA100MetreBoxIsRefusedOnA16GBMachine) {
  const Scene scene = parse_with(
      "  - random: {template: grain, region: {box: {min: [0, 0, 0], max: [100, 100, 100]}}, "
      "count: 100000000}\n");
  try {
    check_scene_memory(scene, 16000000000ull);
    ADD_FAILURE() << "no SceneError";
  } catch (const SceneError& e) {
    EXPECT_STREQ(e.what(),
                 "errors.yaml:17:13: particles[1].random: the scene would create 100000001 "
                 "particles (100000000 of them from this entry), an estimated 204800002048 bytes "
                 "(2048 a particle), more than the 16000000000 bytes of memory this machine has; "
                 "ask for fewer particles");
  }
}

// The machine's memory as the kernel reports it: MemTotal of /proc/meminfo, in kB.
double meminfo_total_bytes() {
  std::ifstream in("/proc/meminfo");
  std::string name;
  double kilobytes = 0;
  in >> name >> kilobytes;
  return name == "MemTotal:" ? kilobytes * 1024 : 0;
}

TEST(SceneMemory, PhysicalMemoryAgreesWithTheKernelsTotal) {
  const double total = meminfo_total_bytes();
  if (total == 0) GTEST_SKIP() << "no /proc/meminfo";
  // MemTotal is the physical pages less what the kernel reserved at boot (a few percent at
  // most), so the two agree within 10%.
  const double physical = double(physical_memory_bytes());
  EXPECT_GE(physical, total);
  EXPECT_LT(physical, 1.1 * total);
}

}  // namespace
}  // namespace talus
