// The scenes bench_scenes runs (bench_scenes.cpp) and the steps it runs of each: the scene files
// of benchmarks/scenes/ (generate.py writes them; each header says what it is) and the built-in
// scene, validation/dodecahedron_packing/scene.yaml. tests/scene/test_benchmark_scenes.cpp checks
// every file against this table (it loads, its time step is stable, it runs long enough).
#pragma once

#include <array>
#include <cstdlib>
#include <string>

namespace talus_bench {

// The source tree the scene files are read from: TALUS_SOURCE_DIR in the environment where set (a
// binary built on one machine and carried to another, scripts/gpu-carry-build, whose tree is
// elsewhere), else the tree it was built from.
inline std::string source_root() {
  const char* given = std::getenv("TALUS_SOURCE_DIR");
  return given && *given ? std::string(given) : std::string(TALUS_SOURCE_DIR);
}

struct SceneCase {
  const char* name;  // the benchmarks' names: scenes/<name>/cpu, scenes/<name>/cuda
  const char* file;  // from the repository root
  // Steps run once per process before any timing, from the scene's start to the state the
  // benchmark measures (a lattice cannot place particles in contact: the loader keeps bounding
  // spheres apart, so a bed first falls together), on the CUDA backend where there is a usable
  // device, else on the host; each variant resumes from its checkpoint, so both backends time
  // the same state. Large scenes are settled on the host only with TALUS_BENCH_SCENE_HOST_SETTLE=1;
  // a settle on the GPU stops early after TALUS_BENCH_SCENE_SETTLE_SECONDS (bench_scenes.cpp).
  long long settle_steps;
  long long warmup_steps;  // each variant, untimed, after the settled state
  long long cuda_steps;    // timed steps on the CUDA backend
  long long host_steps;    // timed steps on the host
  bool large;
};

// Settle lengths from the contact_count probe of `talus run` on the scenes (host, 1 thread):
// the pair contacts level off after these steps (README.md, "Scene benchmarks").
inline constexpr std::array<SceneCase, 6> kSceneCases{{
    // The built-in scene end to end, as `talus run` with no scene runs it: the pour and the bed.
    {"builtin", "validation/dodecahedron_packing/scene.yaml", 0, 0, 17500, 17500, false},
    {"bed_1e4", "benchmarks/scenes/bed_1e4.yaml", 7500, 20, 2000, 250, false},
    {"drum_quasi2d", "benchmarks/scenes/drum_quasi2d.yaml", 15000, 50, 4000, 1000, false},
    {"hopper", "benchmarks/scenes/hopper.yaml", 12500, 20, 2000, 250, false},
    {"drum_1e6", "benchmarks/scenes/drum_1e6.yaml", 17500, 5, 200, 2, true},
    {"bed_1e6", "benchmarks/scenes/bed_1e6.yaml", 12500, 5, 200, 2, true},
}};

}  // namespace talus_bench
