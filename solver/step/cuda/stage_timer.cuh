// The CUDA step's per-stage times (StageSeconds, step_plan.hpp) from pairs of CUDA events around
// each stage's work on the default stream (which the pair stage's blocking streams join), read at
// the end of the step, when the device has caught up anyway: timing never makes the host wait
// for the device. The time is the device's, from the stage's start to its end, with the gaps
// where the device waited for the host's next launch (a small scene's step is mostly such gaps).
// Included only from .cu files.
#pragma once

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
    for (const cudaEvent_t e : spare_) cudaEventDestroy(e);
  }

  // body() between two events recorded for `stage`.
  template <class Body>
  void timed(Stage stage, Body&& body) {
    spare_.reserve(spare_.size() + 2);  // so that handing the events back cannot throw
    const cudaEvent_t start = take_event();
    cudaEvent_t stop = nullptr;
    try {
      stop = take_event();
    } catch (...) {
      spare_.push_back(start);  // not leaked: room was reserved above
      throw;
    }
    marks_.push_back(Mark{stage, start, stop});
    TALUS_CUDA_CHECK(cudaEventRecord(start, 0));
    body();
    TALUS_CUDA_CHECK(cudaEventRecord(stop, 0));
  }

  // The recorded stages' times added to `seconds` (waits for the last one's end).
  void collect(StageSeconds& seconds) {
    for (const Mark& mark : marks_) {
      TALUS_CUDA_CHECK(cudaEventSynchronize(mark.stop));
      float ms = 0;
      TALUS_CUDA_CHECK(cudaEventElapsedTime(&ms, mark.start, mark.stop));
      seconds[static_cast<int>(mark.stage)] += 1e-3 * double(ms);
      spare_.push_back(mark.start);
      spare_.push_back(mark.stop);
    }
    marks_.clear();
  }

 private:
  struct Mark {
    Stage stage;
    cudaEvent_t start, stop;
  };

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
  std::vector<cudaEvent_t> spare_;  // created and free
};

}  // namespace talus
