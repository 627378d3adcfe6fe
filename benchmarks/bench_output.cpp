// Writing one trajectory frame (solver/io/trajectory.hpp) of N particles as CSV and as HDF5: the
// wall time a frame costs a run and the bytes it leaves on disk (counter `bytes`). The issue's
// target for large runs: a frame of 1e6 particles in under 1 s and under 100 MB. The rows are
// random (positions in a 1 m box, unit quaternions, speeds up to 1 m/s): text digits and the
// file size do not depend on a simulation.
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "solver/io/output_files.hpp"
#include "solver/io/trajectory.hpp"

namespace {

std::vector<talus::TrajectoryRow> random_rows(long long count) {
  std::mt19937_64 random(11);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::vector<talus::TrajectoryRow> rows(count);
  for (long long i = 0; i < count; ++i) {
    talus::TrajectoryRow& r = rows[i];
    r.id = i;
    r.template_index = static_cast<int>(i % 3);
    r.position = {unit(random), unit(random), unit(random)};
    r.orientation =
        talus::Quatd(unit(random), unit(random), unit(random), unit(random)).normalized();
    r.velocity = {unit(random), unit(random), unit(random)};
    r.angular_velocity = {100 * unit(random), 100 * unit(random), 100 * unit(random)};
  }
  return rows;
}

void write_frame(benchmark::State& state, bool hdf5) {
  const std::vector<talus::TrajectoryRow> rows = random_rows(state.range(0));
  const std::string dir =
      (std::filesystem::temp_directory_path() / ("talus-bench-output-" + std::to_string(getpid())))
          .string();
  talus::create_output_directory(dir);
  long long step = 0;
  for (auto _ : state) {
    if (hdf5) {
      talus::write_trajectory_frame_hdf5(dir, step, 0.0, rows);
    } else {
      talus::write_trajectory_frame(dir, step, rows);
    }
    ++step;
  }
  const std::string file = dir + "/" +
                           talus::trajectory_file_name(0, hdf5 ? talus::TrajectoryFormat::hdf5
                                                               : talus::TrajectoryFormat::csv);
  state.counters["bytes"] = static_cast<double>(std::filesystem::file_size(file));
  state.counters["particles_per_second"] = benchmark::Counter(
      static_cast<double>(rows.size()), benchmark::Counter::kIsIterationInvariantRate);
  std::filesystem::remove_all(dir);
}

BENCHMARK_CAPTURE(write_frame, csv, false)->Arg(10000)->Arg(1000000)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(write_frame, hdf5, true)->Arg(10000)->Arg(1000000)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
