// The host backend's loops on several threads (OpenMP). Every loop here writes each index's result
// to its own slot, so what a loop computes does not depend on the thread count or the schedule;
// anything summed over indices is summed afterwards in a fixed order by the caller. Without
// OpenMP (a compiler without it, or nvcc, which is not given -fopenmp) the loops are plain serial
// loops: the pragmas are not even seen, so a .cu file may include the headers that use these. It
// must not run their host loops, though: its copies would be the serial ones, and a program keeps
// one copy of each template instance (the host drivers are run from C++ files only).
#pragma once

#ifdef _OPENMP
#include <omp.h>
#endif

namespace talus {

// Below this many indices a loop of cheap per-index work (a few to a hundred nanoseconds each)
// runs on the calling thread alone: starting and joining the threads costs microseconds when the
// cores are idle, and a whole time slice (milliseconds) when another process holds one of them,
// which made a two-particle scene many times slower on two busy cores
// (benchmarks/history/README.md).
constexpr long long kParallelMinIndices = 1024;

// The threads a host loop uses when the caller asks for `requested` (<= 0: OpenMP's default, all
// cores or OMP_NUM_THREADS); 1 without OpenMP.
inline int host_thread_count(int requested = 0) {
#ifdef _OPENMP
  return requested > 0 ? requested : omp_get_max_threads();
#else
  (void)requested;
  return 1;
#endif
}

// Makes `threads` what host_thread_count(0) gives from now on (OpenMP's default for this
// process): a rank of a decomposed run sets its share of the cores, so that the loops that take
// the default (making and checking the initial particles) do not each start a thread a core.
inline void set_default_host_threads(int threads) {
#ifdef _OPENMP
  if (threads > 0) omp_set_num_threads(threads);
#else
  (void)threads;
#endif
}

// The calling thread's index within the running loop: 0 .. threads - 1 (per-thread scratch).
inline int host_thread_index() {
#ifdef _OPENMP
  return omp_get_thread_num();
#else
  return 0;
#endif
}

// body(i) for i in [0, n) in equal blocks, one per thread: for work that is the same per index
// (the per-particle stages). body must not throw (an exception cannot leave an OpenMP loop).
template <class Body>
void parallel_for(int threads, long long n, Body&& body) {
  const bool parallel = threads > 1 && n >= kParallelMinIndices;
  (void)parallel;
#ifdef _OPENMP
#pragma omp parallel for num_threads(threads) schedule(static) if (parallel)
#endif
  for (long long i = 0; i < n; ++i) body(i);
}

// The same with chunks of `chunk` indices handed to whichever thread is free: for work that
// costs microseconds and varies per index (a touching pair costs an overlap, a distant one a
// bounding-sphere test). On one thread while there is a single chunk.
template <class Body>
void parallel_for_dynamic(int threads, long long n, int chunk, Body&& body) {
  const bool parallel = threads > 1 && n > chunk;
  (void)parallel;
#ifdef _OPENMP
#pragma omp parallel for num_threads(threads) schedule(dynamic, chunk) if (parallel)
#endif
  for (long long i = 0; i < n; ++i) body(i);
}

// Calls fails(i) for every i in [0, n) and returns the lowest i for which it returned true (n if
// none): the serial loop's first failure, whatever the thread count.
template <class Fails>
long long parallel_first_failure(int threads, long long n, Fails&& fails) {
  const bool parallel = threads > 1 && n >= kParallelMinIndices;
  (void)parallel;
  long long first = n;
#ifdef _OPENMP
#pragma omp parallel for num_threads(threads) reduction(min : first) if (parallel)
#endif
  for (long long i = 0; i < n; ++i) {
    if (fails(i) && i < first) first = i;
  }
  return first;
}

}  // namespace talus
