// The CUDA step's per-stage times (StageSeconds, step_plan.hpp) from pairs of CUDA events around
// each stage's work on the step's stream (which the pair stage's side streams join), read at the
// end of the step, when the device has caught up anyway: timing never makes the host wait for
// the device. The time is the device's, from the stage's start to its end, with the gaps where
// the device waited for the host's next launch (a small scene's step launched stage by stage is
// mostly such gaps). While a step is captured into a graph, the events become the graph's own
// event-record nodes (cudaEventRecordExternal), kept with the graph and read after each launch.
// Included only from .cu files.
#pragma once

#include <cstdlib>
#include <string>
#include <vector>

#include "solver/core/cuda_check.hpp"
#include "solver/step/step_plan.hpp"

namespace talus {

class StageTimer {
 public:
  StageTimer() = default;
  StageTimer(const StageTimer&) = delete;
  StageTimer& operator=(const StageTimer&) = delete;
  ~StageTimer() {
    for (const Mark& mark : marks_) cudaEventDestroy(mark.start), cudaEventDestroy(mark.stop);
    for (const Mark& mark : graph_marks_) cudaEventDestroy(mark.start), cudaEventDestroy(mark.stop);
    for (const cudaEvent_t e : spare_) cudaEventDestroy(e);
  }

  // body() between two events recorded for `stage` on `stream`; while `capturing`, as nodes of
  // the graph (kept until release_graph).
  template <class Body>
  void timed(Stage stage, cudaStream_t stream, bool capturing, Body&& body) {
    if (!enabled()) return body();
    spare_.reserve(spare_.size() + 2);  // so that handing the events back cannot throw
    const cudaEvent_t start = take_event();
    cudaEvent_t stop = nullptr;
    try {
      stop = take_event();
    } catch (...) {
      spare_.push_back(start);  // not leaked: room was reserved above
      throw;
    }
    std::vector<Mark>& marks = capturing ? graph_marks_ : marks_;
    marks.push_back(Mark{stage, start, stop});
    const unsigned flags = capturing ? cudaEventRecordExternal : cudaEventRecordDefault;
    TALUS_CUDA_CHECK(cudaEventRecordWithFlags(start, stream, flags));
    body();
    TALUS_CUDA_CHECK(cudaEventRecordWithFlags(stop, stream, flags));
  }

  // After a launch of the graph: its stages' times added to `seconds` (waits for the last one).
  void collect_graph(StageSeconds& seconds) { add(graph_marks_, seconds); }
  // The graph's events back to the spares (the graph is gone).
  void release_graph() {
    for (const Mark& mark : graph_marks_) spare_.push_back(mark.start), spare_.push_back(mark.stop);
    graph_marks_.clear();
  }

  // The recorded stages' times added to `seconds` (waits for the last one's end).
  void collect(StageSeconds& seconds) {
    add(marks_, seconds);
    for (const Mark& mark : marks_) spare_.push_back(mark.start), spare_.push_back(mark.stop);
    marks_.clear();
  }

 private:
  struct Mark {
    Stage stage;
    cudaEvent_t start, stop;
  };

  // TALUS_STAGE_TIMES=0 in the environment: no events (to measure what the events cost).
  static bool enabled() {
    static const bool on = [] {
      const char* v = std::getenv("TALUS_STAGE_TIMES");
      return v == nullptr || std::string(v) != "0";
    }();
    return on;
  }

  static void add(const std::vector<Mark>& marks, StageSeconds& seconds) {
    for (const Mark& mark : marks) {
      TALUS_CUDA_CHECK(cudaEventSynchronize(mark.stop));
      float ms = 0;
      TALUS_CUDA_CHECK(cudaEventElapsedTime(&ms, mark.start, mark.stop));
      seconds[static_cast<int>(mark.stage)] += 1e-3 * double(ms);
    }
  }

  cudaEvent_t take_event() {
    if (spare_.empty()) {
      cudaEvent_t e = nullptr;
      TALUS_CUDA_CHECK(cudaEventCreate(&e));
      return e;
    }
    const cudaEvent_t e = spare_.back();
    spare_.pop_back();
    return e;
  }

  std::vector<Mark> marks_;         // recorded this step, not read yet
  std::vector<Mark> graph_marks_;   // nodes of the step's graph
  std::vector<cudaEvent_t> spare_;  // created and free
};

}  // namespace talus
