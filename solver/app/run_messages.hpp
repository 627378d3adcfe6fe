// What `talus run` tells on stderr while it runs (run_command.cpp): the progress line of either
// solver, each part of the setup as it ends (and the summary's setup_seconds), and the warning
// for a node whose ranks start more threads than it has cores.
#pragma once

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

namespace talus {

struct ProductionProgress;  // solver/run/production_run.hpp
struct RunArguments;        // run_arguments.hpp

// One progress line on stderr, the same for both solvers, `more` at its end (the production
// run's: its feeds that have fallen behind, "  feeds behind: 1 of 19 due inserted").
void print_progress_line(long long step, long long total_steps, double time, double end_time,
                         std::size_t particles, std::size_t contacts, double wall_seconds,
                         const std::string& more = "");
void print_production_progress(const ProductionProgress& p);

// The parts of a run's setup, timed in order: the command's (the scene and its walls read, the
// initial particles made and checked) and the runner's (ProductionSettings::setup_done: "step",
// "restore", "first_forces"). Each is told on stderr as it ends (rank 0, unless --quiet), so
// that a run of millions of particles that takes minutes before its first step says where they
// go, and a run killed in its setup leaves that behind in its log; the summary has them as
// setup_seconds.
class SetupTimes {
 public:
  explicit SetupTimes(bool quiet);
  // `part` ended now (its seconds: since the last part ended); `what` says it on stderr.
  void done(const std::string& part, const std::string& what);
  // The runner's part `part` (its name is its key) took `seconds`.
  void runner_part(const std::string& part, double seconds);
  const std::vector<std::pair<std::string, double>>& parts() const { return parts_; }

 private:
  void add(const std::string& part, const std::string& what, double seconds);
  bool tell_;
  double mark_;
  std::vector<std::pair<std::string, double>> parts_;
};

// A decomposed run whose ranks on one node, with --threads T > 1 each, start more threads than
// the node has cores: each rank's OpenMP loops then wait at their barriers for threads that have
// no core (the random fill waits for every thread after each batch). Said once, by rank 0, also
// with --quiet; the run goes on.
void warn_oversubscribed_threads(const RunArguments& args);

}  // namespace talus
