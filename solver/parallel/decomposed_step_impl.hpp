// The decomposed run's command loop for any production step type (decomposed_step.hpp): the
// host step's instance is decomposed_step.cpp's, the CUDA step's cuda_decomposed_step.cu's.
#pragma once

#include <algorithm>
#include <cmath>
#include <exception>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "solver/io/checkpoint.hpp"
#include "solver/parallel/decomposed_step.hpp"
#include "solver/step/step_state.hpp"

namespace talus {

// Whether this process has sent (rank 0) or received the end of the run.
bool& decomposed_run_ended();

namespace decomposed_detail {

// Rank 0's calls, as the other ranks receive them.
enum Command : int {
  kEnd = 0,
  kStep,
  kEvaluate,
  kParticles,
  kRemoved,
  kPairContacts,
  kListBuilds,
  kWallContacts,
  kWallForce,
  kWallTorque,
  kRows,
  kKinetic,
  kEnergy,
  kBedHeight,
  kBytes,
  kSave,
  kRestore,
  kExchangeSeconds,
  kRebalances,
  kExchangeBytes,
};

// Sums of several numbers over the ranks, added in rank order (the same bits on every rank and
// in every run of the same rank count).
inline std::vector<double> sums(const Communicator& comm, const std::vector<double>& mine) {
  Bytes bytes;
  ByteWriter(bytes).put_vector(mine);
  std::vector<double> total(mine.size(), 0.0);
  for (const Bytes& b : comm.all_gather(bytes)) {
    ByteReader in(b);
    const std::vector<double> v = in.get_vector<double>();
    for (std::size_t k = 0; k < total.size(); ++k) total[k] += v.at(k);
  }
  return total;
}

// A command as rank 0 broadcasts it, in one collective: its number, its argument and its text (a
// checkpoint's path) when the text fits; a longer text follows in a broadcast of its own.
struct CommandMessage {
  int command = 0, argument = 0;
  long long text_size = 0;
  char text[240] = {};
};

inline void send_command(const Communicator& comm, int command, int argument,
                         const std::string& text) {
  CommandMessage m;
  m.command = command;
  m.argument = argument;
  m.text_size = static_cast<long long>(text.size());
  text.copy(m.text, std::min(text.size(), sizeof m.text));
  comm.broadcast(reinterpret_cast<char*>(&m), sizeof m, 0);
  if (text.size() > sizeof m.text) {
    Bytes bytes(text.begin(), text.end());
    comm.broadcast(bytes, 0);
  }
}

// The other ranks' side of send_command: the command, with its text in `text`.
inline CommandMessage receive_command(const Communicator& comm, std::string& text) {
  CommandMessage m;
  comm.broadcast(reinterpret_cast<char*>(&m), sizeof m, 0);
  if (m.text_size > static_cast<long long>(sizeof m.text)) {
    Bytes bytes;
    comm.broadcast(bytes, 0);
    text.assign(bytes.begin(), bytes.end());
  } else {
    text.assign(m.text, static_cast<std::size_t>(m.text_size));
  }
  return m;
}

// What a command returns on rank 0.
struct Answer {
  std::vector<double> numbers;
  std::vector<TrajectoryRow> rows;
};

// One step decomposed over the ranks, and the commands on it, run alike on every rank.
// `Step`: HostStep<Real> or CudaStep<Real>, made by `make`.
template <class Step>
class Decomposed {
 public:
  using Real = typename Step::real_type;
  Decomposed(const Scene& scene, std::shared_ptr<const Communicator> comm,
             const std::function<std::unique_ptr<Step>()>& make)
      : scene_(scene), comm_(comm), owned_step_(make()), step_(*owned_step_) {}

  // Runs `command` (with `argument`, `text`) on this rank; every rank must call it in turn.
  Answer run(int command, int argument, const std::string& text, Checkpoint* save) {
    std::exception_ptr failure;
    Answer a;
    try {
      a = work(command, argument, text, save);
    } catch (...) {
      failure = std::current_exception();
    }
    agree_on_failure(*comm_, failure);
    return a;
  }

  Step& step() { return step_; }

 private:
  Answer work(int command, int argument, const std::string& text, Checkpoint* save) {
    const Communicator& c = *comm_;
    Answer a;
    switch (command) {
      case kStep:
        step_.step();
        break;
      case kEvaluate:
        step_.evaluate_forces();
        break;
      case kParticles:
        a.numbers = sums(c, {double(step_.particle_count())});
        break;
      case kRemoved:
        a.numbers = sums(c, {double(step_.removed_count())});
        break;
      case kPairContacts:
        a.numbers = sums(c, {double(step_.pair_contact_count())});
        break;
      case kListBuilds:
        a.numbers = {c.max(double(step_.pair_list_builds()))};
        break;
      case kWallContacts:
        a.numbers = sums(c, {double(step_.wall_contact_count())});
        break;
      case kWallForce:
      case kWallTorque: {
        const Vec3d v =
            command == kWallForce ? step_.wall_force(argument) : step_.wall_torque(argument);
        a.numbers = sums(c, {v.x, v.y, v.z});
        break;
      }
      case kRows: {
        Bytes bytes;
        ByteWriter(bytes).put_vector(step_.trajectory_rows());
        for (const Bytes& b : c.all_gather(bytes)) {
          ByteReader in(b);
          const std::vector<TrajectoryRow> rows = in.get_vector<TrajectoryRow>();
          a.rows.insert(a.rows.end(), rows.begin(), rows.end());
        }
        std::sort(a.rows.begin(), a.rows.end(),
                  [](const TrajectoryRow& x, const TrajectoryRow& y) { return x.id < y.id; });
        break;
      }
      case kKinetic:
        a.numbers = sums(c, {step_.kinetic_energy()});
        break;
      case kEnergy: {
        const EnergyTerms e = step_.energy();
        const EnergyLedger& l = e.ledger;
        a.numbers = sums(c, {e.kinetic_translational, e.kinetic_rotational, e.gravitational,
                             e.elastic_normal, e.elastic_tangential, l.dissipated, l.wall_work,
                             l.fed, l.removed, l.dissipation_rate, l.wall_power, l.spring_energy});
        break;
      }
      case kBedHeight: {
        // The highest point over the ranks that hold particles.
        const double mine =
            step_.particle_count() > 0 ? step_.bed_height(*scene_.effects.gravity) : -HUGE_VAL;
        const double top = c.max(mine);
        a.numbers = {std::isfinite(top) ? top : 0.0};
        break;
      }
      case kBytes:
        a.numbers = sums(c, {double(step_.allocated_bytes())});
        break;
      case kSave: {
        const StepState<Real> s = step_.export_state();  // every rank's, on every rank
        if (save) put_step_state(*save, s);
        break;
      }
      case kExchangeSeconds:
        a.numbers = {c.max(step_.exchange_seconds()), c.max(step_.exchange_vote_seconds()),
                     c.max(step_.exchange_rebuild_seconds())};
        break;
      case kExchangeBytes:
        a.numbers = sums(c, {step_.exchange_bytes()});
        break;
      case kRebalances:
        a.numbers = {double(step_.rebalances())};  // the same on every rank
        break;
      case kRestore:
        step_.import_state(get_step_state<Real>(read_checkpoint(text)));
        break;
      default:
        throw std::runtime_error("decomposed step: unknown command " + std::to_string(command));
    }
    return a;
  }

  const Scene& scene_;
  std::shared_ptr<const Communicator> comm_;
  std::unique_ptr<Step> owned_step_;
  Step& step_;
};

template <class Step>
class DecomposedStep final : public AnyStep {
 public:
  DecomposedStep(const Scene& scene, std::shared_ptr<const Communicator> comm,
                 const std::function<std::unique_ptr<Step>()>& make, const char* backend)
      : comm_(comm), d_(scene, comm, make), whole_(Box(), 0), backend_(backend) {}
  ~DecomposedStep() override { end_decomposed_run(*comm_); }

  const char* backend() const override { return backend_; }
  void step() override { call(kStep); }
  void evaluate_forces() override { call(kEvaluate); }
  double time() const override { return d_.step().time(); }
  const StepPlan& plan() const override { return d_.step().plan(); }
  std::size_t particles() const override { return number(kParticles); }
  // The numbers this step reports are the whole run's already: the probes' sums over ranks are
  // the numbers themselves.
  const Domain& domain() const override { return whole_; }
  long long removed_particles() const override { return number(kRemoved); }
  std::size_t pair_contacts() const override { return number(kPairContacts); }
  long long pair_list_builds() const override { return number(kListBuilds); }
  std::size_t wall_contacts() const override { return number(kWallContacts); }
  Vec3d wall_force(int w) const override { return vector(kWallForce, w); }
  Vec3d wall_torque(int w) const override { return vector(kWallTorque, w); }
  std::vector<TrajectoryRow> rows() const override { return call(kRows).rows; }
  double kinetic_energy() const override { return call(kKinetic).numbers.at(0); }
  EnergyTerms energy() const override {
    const std::vector<double> n = call(kEnergy).numbers;
    EnergyTerms e;
    e.kinetic_translational = n.at(0), e.kinetic_rotational = n.at(1), e.gravitational = n.at(2);
    e.elastic_normal = n.at(3), e.elastic_tangential = n.at(4);
    EnergyLedger& l = e.ledger;
    l.dissipated = n.at(5), l.wall_work = n.at(6), l.fed = n.at(7), l.removed = n.at(8);
    l.dissipation_rate = n.at(9), l.wall_power = n.at(10), l.spring_energy = n.at(11);
    return e;
  }
  double bed_height(const Vec3d&) const override { return call(kBedHeight).numbers.at(0); }
  // Rank 0's stage times (each rank times its own).
  const StageSeconds& stage_seconds() const override { return d_.step().stage_seconds(); }
  std::size_t bytes() const override { return number(kBytes); }
  double exchange_seconds() const override { return call(kExchangeSeconds).numbers.at(0); }
  double exchange_vote_seconds() const override { return call(kExchangeSeconds).numbers.at(1); }
  double exchange_rebuild_seconds() const override { return call(kExchangeSeconds).numbers.at(2); }
  double exchange_bytes() const override { return call(kExchangeBytes).numbers.at(0); }
  long long rebalances() const override { return number(kRebalances); }
  // Every rank runs every feed on every particle: rank 0's counts are the run's.
  std::vector<FeedCount> feed_counts() const override { return d_.step().feed_counts(); }
  void save_state(Checkpoint& checkpoint) const override { call(kSave, 0, "", &checkpoint); }
  void restore_state(const Checkpoint& checkpoint) override {
    call(kRestore, 0, checkpoint.path());
  }

 private:
  Answer call(int command, int argument = 0, const std::string& text = "",
              Checkpoint* save = nullptr) const {
    send_command(*comm_, command, argument, text);
    return d_.run(command, argument, text, save);
  }
  long long number(int command) const {
    return static_cast<long long>(std::llround(call(command).numbers.at(0)));
  }
  Vec3d vector(int command, int w) const {
    const std::vector<double> n = call(command, w).numbers;
    return Vec3d(n.at(0), n.at(1), n.at(2));
  }

  std::shared_ptr<const Communicator> comm_;
  mutable Decomposed<Step> d_;
  SingleDomain whole_;
  const char* backend_;
};

template <class Step>
void serve(const Scene& scene, std::shared_ptr<const Communicator> comm,
           const std::function<std::unique_ptr<Step>()>& make) {
  Decomposed<Step> d(scene, comm, make);
  for (;;) {
    std::string text;
    const CommandMessage m = receive_command(*comm, text);
    if (m.command == kEnd) {
      decomposed_run_ended() = true;
      return;
    }
    try {
      d.run(m.command, m.argument, text, nullptr);
    } catch (const std::exception&) {
      // Every rank failed with this message (agree_on_failure); rank 0 reports it.
    }
  }
}

}  // namespace decomposed_detail

}  // namespace talus
