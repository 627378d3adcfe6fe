// The production step of either backend (host_step.hpp, cuda_step.hpp) in either precision
// behind one interface, for the runner (production_run.hpp): host code, a virtual call per step.
#pragma once

#include <array>
#include <cstddef>
#include <memory>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "solver/io/trajectory.hpp"
#include "solver/scene/feeder.hpp"
#include "solver/scene/scene.hpp"
#include "solver/step/step_plan.hpp"
#include "solver/step/step_state.hpp"

namespace talus {

class AnyStep {
 public:
  virtual ~AnyStep() = default;
  virtual const char* backend() const = 0;  // "cpu" or "cuda", as run.json writes it
  virtual void step() = 0;
  virtual void evaluate_forces() = 0;
  virtual double time() const = 0;
  virtual const StepPlan& plan() const = 0;
  virtual std::size_t particles() const = 0;
  // The local domain (domain/domain.hpp): probes combine their numbers over its ranks.
  virtual const Domain& domain() const = 0;
  virtual long long removed_particles() const = 0;  // left the domain box so far
  virtual std::size_t pair_contacts() const = 0;
  virtual long long pair_list_builds() const = 0;  // builds of the pair list so far
  virtual std::size_t wall_contacts() const = 0;
  virtual Vec3d wall_force(int w) const = 0;
  virtual Vec3d wall_torque(int w) const = 0;
  virtual std::vector<TrajectoryRow> rows() const = 0;
  virtual double kinetic_energy() const = 0;
  virtual EnergyTerms energy() const = 0;
  virtual double bed_height(const Vec3d& gravity) const = 0;
  virtual const StageSeconds& stage_seconds() const = 0;
  virtual std::size_t bytes() const = 0;
  // Seconds spent exchanging particles between ranks (a decomposed step; 0 in one process).
  virtual double exchange_seconds() const { return 0; }
  // Of those: the rebuild vote's (the wait for the slowest rank included) and the rebuild
  // steps' (migration, the ghosts chosen again); the rest is the ghosts' updates.
  virtual double exchange_vote_seconds() const { return 0; }
  virtual double exchange_rebuild_seconds() const { return 0; }
  // Decomposed: the bytes every rank sent to the others so far, summed (ghosts, migrations).
  virtual double exchange_bytes() const { return 0; }
  // Times the ranks' boxes were cut again (a decomposed step; 0 in one process).
  virtual long long rebalances() const { return 0; }
  // The CUDA step's graph steps (cuda_step_impl.cuh): the steps launched as one graph, the
  // graphs captured, and the graph steps whose wall stage overran and finished stage by stage;
  // zeros for a step without graphs.
  struct GraphSteps {
    long long steps = 0, captures = 0, aborted = 0;
  };
  virtual GraphSteps graph_steps() const { return {}; }
  // The stages that ran on a stream of their own beside another stage, each with that stage
  // (the CUDA step's wall stage beside its pair stage): their seconds overlap that stage's, so
  // a step lasts less than the sum of its stages' seconds. None for the host step.
  virtual std::vector<std::pair<std::string, std::string>> stages_beside() const { return {}; }
  // The scene's feeds' progress now, in the scene's order (none: no feed).
  virtual std::vector<FeedCount> feed_counts() const = 0;
  // The step's state as checkpoint sections (step_state.hpp), and the state set back from them
  // on a step made from the same scene (CheckpointError when they do not fit it).
  virtual void save_state(Checkpoint& checkpoint) const = 0;
  virtual void restore_state(const Checkpoint& checkpoint) = 0;
};

// Whether Step reports graph steps (CudaStep::graph_counts).
template <class Step, class = void>
struct has_graph_counts : std::false_type {};
template <class Step>
struct has_graph_counts<Step, std::void_t<decltype(std::declval<const Step&>().graph_counts())>>
    : std::true_type {};

// Whether Step runs stages beside others (CudaStep::stages_beside).
template <class Step, class = void>
struct has_stages_beside : std::false_type {};
template <class Step>
struct has_stages_beside<Step, std::void_t<decltype(std::declval<const Step&>().stages_beside())>>
    : std::true_type {};

// AnyStep over a step class with HostStep's interface (HostStep<Real>, CudaStep<Real>); `args`
// follow the scene in the step's constructor (HostStep: its threads).
template <class Step>
class StepAdapter : public AnyStep {
 public:
  template <class... Args>
  StepAdapter(const Scene& scene, const char* backend, Args... args)
      : step_(scene, args...), backend_(backend) {}
  const char* backend() const override { return backend_; }
  void step() override { step_.step(); }
  void evaluate_forces() override { step_.evaluate_forces(); }
  double time() const override { return step_.time(); }
  const StepPlan& plan() const override { return step_.plan(); }
  std::size_t particles() const override { return step_.particle_count(); }
  const Domain& domain() const override { return step_.domain(); }
  long long removed_particles() const override { return step_.removed_count(); }
  std::size_t pair_contacts() const override { return step_.pair_contact_count(); }
  long long pair_list_builds() const override { return step_.pair_list_builds(); }
  std::size_t wall_contacts() const override { return step_.wall_contact_count(); }
  Vec3d wall_force(int w) const override { return step_.wall_force(w); }
  Vec3d wall_torque(int w) const override { return step_.wall_torque(w); }
  std::vector<TrajectoryRow> rows() const override { return step_.trajectory_rows(); }
  double kinetic_energy() const override { return step_.kinetic_energy(); }
  EnergyTerms energy() const override { return step_.energy(); }
  double bed_height(const Vec3d& g) const override { return step_.bed_height(g); }
  const StageSeconds& stage_seconds() const override { return step_.stage_seconds(); }
  std::size_t bytes() const override { return step_.allocated_bytes(); }
  std::vector<FeedCount> feed_counts() const override { return step_.feed_counts(); }
  GraphSteps graph_steps() const override {
    if constexpr (has_graph_counts<Step>::value) {
      const auto c = step_.graph_counts();
      return {c.steps, c.captures, c.aborted};
    } else {
      return {};
    }
  }
  std::vector<std::pair<std::string, std::string>> stages_beside() const override {
    if constexpr (has_stages_beside<Step>::value) {
      return step_.stages_beside();
    } else {
      return {};
    }
  }
  void save_state(Checkpoint& checkpoint) const override {
    put_step_state(checkpoint, step_.export_state());
  }
  void restore_state(const Checkpoint& checkpoint) override {
    step_.import_state(get_step_state<typename Step::real_type>(checkpoint));
  }

 private:
  Step step_;
  const char* backend_;
};

// The host step in the scene's precision on `threads` threads (<= 0: OpenMP's default).
std::unique_ptr<AnyStep> make_host_step(const Scene& scene, int threads = 0);

}  // namespace talus
