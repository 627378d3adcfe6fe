#include "solver/parallel/decomposed_step.hpp"

#include <memory>

#include "solver/parallel/decomposed_step_impl.hpp"
#include "solver/step/host/host_step.hpp"

namespace talus {

namespace {

std::shared_ptr<const Communicator>& world_slot() {
  static std::shared_ptr<const Communicator> comm = std::make_shared<SerialCommunicator>();
  return comm;
}

template <class Real>
std::function<std::unique_ptr<HostStep<Real>>()> host_maker(
    const Scene& scene, int threads, const std::shared_ptr<const Communicator>& comm) {
  return [&scene, threads, comm] { return std::make_unique<HostStep<Real>>(scene, threads, comm); };
}

}  // namespace

bool& decomposed_run_ended() {
  static bool ended = false;
  return ended;
}

std::unique_ptr<AnyStep> make_decomposed_step(const Scene& scene, int threads,
                                              std::shared_ptr<const Communicator> comm) {
  using decomposed_detail::DecomposedStep;
  if (scene.precision == Precision::float32)
    return std::make_unique<DecomposedStep<HostStep<float>>>(
        scene, comm, host_maker<float>(scene, threads, comm), "cpu");
  return std::make_unique<DecomposedStep<HostStep<double>>>(
      scene, comm, host_maker<double>(scene, threads, comm), "cpu");
}

void serve_decomposed_step(const Scene& scene, int threads,
                           std::shared_ptr<const Communicator> comm) {
  if (scene.precision == Precision::float32)
    return decomposed_detail::serve<HostStep<float>>(scene, comm,
                                                     host_maker<float>(scene, threads, comm));
  decomposed_detail::serve<HostStep<double>>(scene, comm, host_maker<double>(scene, threads, comm));
}

void set_world(std::shared_ptr<const Communicator> comm) {
  world_slot() = std::move(comm);
}
const std::shared_ptr<const Communicator>& world() {
  return world_slot();
}

void end_decomposed_run(const Communicator& comm) {
  bool& ended = decomposed_run_ended();
  if (ended || comm.size() == 1) return;
  if (comm.rank() == 0) {
    decomposed_detail::send_command(comm, decomposed_detail::kEnd, 0, "");
    ended = true;
    return;
  }
  // A rank that is not serving: rank 0 found the same fault and ends the run.
  std::string text;
  while (decomposed_detail::receive_command(comm, text).command != decomposed_detail::kEnd) {
  }
  ended = true;
}

}  // namespace talus
