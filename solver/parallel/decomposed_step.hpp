// `mpirun -np N talus run` on the host backend (docs/parallel.md): the production step decomposed
// over N ranks (HostStep with a Communicator: each rank its box of particles and its ghosts).
// Rank 0 runs the runner (production_run.hpp) as one process does, over a DecomposedStep: an
// AnyStep whose every call is broadcast to the other ranks as a command, which they serve
// (serve_decomposed_step) until rank 0 ends the run. So every output, probe and checkpoint is
// written once, by rank 0, with the numbers of the whole run (sums and maxima over the ranks,
// rows gathered in global-id order, the state of one process), and nothing above the step knows
// that it is decomposed.
#pragma once

#include <memory>

#include "solver/domain/communicator.hpp"
#include "solver/run/any_step.hpp"
#include "solver/scene/scene.hpp"

namespace talus {

// Rank 0's step: the host step of `scene` in its precision on `threads` threads, decomposed over
// `comm`'s ranks. Its destructor ends the other ranks' serving (end_decomposed_run).
std::unique_ptr<AnyStep> make_decomposed_step(const Scene& scene, int threads,
                                              std::shared_ptr<const Communicator> comm);

// Every other rank: the same step, serving rank 0's commands until it ends the run. A command
// that fails fails on every rank with the same message (agree_on_failure): rank 0 reports it and
// the others go on serving.
void serve_decomposed_step(const Scene& scene, int threads,
                           std::shared_ptr<const Communicator> comm);

// Rank 0: tells the other ranks the run is over (once; later calls do nothing). The others: waits
// for that, when they are not serving (a rank whose step could not be made). Every rank calls it
// before it exits, whatever went wrong, so that none is left waiting.
void end_decomposed_run(const Communicator& comm);

// This process's world (main sets it from its MpiSession; one rank until then).
void set_world(std::shared_ptr<const Communicator> comm);
const std::shared_ptr<const Communicator>& world();

}  // namespace talus
