#include "solver/app/run_messages.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>
#include <thread>

#include <fmt/format.h>

#include "solver/app/run_arguments.hpp"
#include "solver/parallel/decomposed_step.hpp"
#include "solver/run/production_run.hpp"

namespace talus {

namespace {

double clock_now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

}  // namespace

void print_progress_line(long long step, long long total_steps, double time, double end_time,
                         std::size_t particles, std::size_t contacts, double wall_seconds,
                         const std::string& more) {
  const double fraction = total_steps > 0 ? double(step) / double(total_steps) : 1.0;
  const double left = fraction > 0 ? wall_seconds * (1 - fraction) / fraction : 0;
  std::fprintf(stderr,
               "talus run: %5.1f%%  t = %.6g of %.6g s  step %lld of %lld  %.3g steps/s  "
               "%zu particles  %zu contacts  about %.0f s left%s\n",
               100 * fraction, time, end_time, step, total_steps,
               wall_seconds > 0 ? double(step) / wall_seconds : 0.0, particles, contacts, left,
               more.c_str());
}

void print_production_progress(const ProductionProgress& p) {
  // Feeds that have fallen behind (their regions full), while the run goes on: the summary and
  // its stderr line say it only at the end.
  long long inserted = 0, due = 0;
  for (const FeedCount& c : p.feeds) {
    if (c.inserted < c.due) inserted += c.inserted, due += c.due;
  }
  const std::string more =
      due > 0 ? fmt::format("  feeds behind: {} of {} due inserted", inserted, due) : "";
  print_progress_line(p.step, p.total_steps, p.time, p.end_time, p.particles, p.contacts,
                      p.wall_seconds, more);
}

SetupTimes::SetupTimes(bool quiet) : tell_(!quiet && world()->rank() == 0), mark_(clock_now()) {}

void SetupTimes::done(const std::string& part, const std::string& what) {
  add(part, what, clock_now() - mark_);
}

void SetupTimes::runner_part(const std::string& part, double seconds) {
  add(part,
      part == "step"      ? "the step built"
      : part == "restore" ? "the checkpoint restored"
                          : "step 0's contacts and outputs",
      seconds);
}

void SetupTimes::add(const std::string& part, const std::string& what, double seconds) {
  parts_.emplace_back(part, seconds);
  mark_ = clock_now();
  if (tell_) std::fprintf(stderr, "talus run: setup: %s in %.1f s\n", what.c_str(), seconds);
}

void warn_oversubscribed_threads(const RunArguments& args) {
  const Communicator& w = *world();
  if (w.size() <= 1 || args.threads <= 1 || w.rank() != 0) return;
  const unsigned cores = std::thread::hardware_concurrency();
  const long long threads = static_cast<long long>(w.node_size()) * args.threads;
  if (cores == 0 || threads <= static_cast<long long>(cores)) return;
  const int share = std::max(1, static_cast<int>(cores) / w.node_size());
  std::fprintf(stderr,
               "talus run: warning: %d ranks on this node with --threads %d each start %lld "
               "threads on its %u cores: each rank's loops then wait for threads that have no "
               "core; drop --threads (each rank then takes its share, %d) or give at most %d\n",
               w.node_size(), args.threads, threads, cores, share, share);
}

}  // namespace talus
