#include "solver/run/production_run.hpp"

#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <variant>

#include "solver/core/host_parallel.hpp"
#include "solver/io/checkpoint.hpp"
#include "solver/io/input_files.hpp"
#include "solver/io/output_files.hpp"
#include "solver/io/output_schedule.hpp"
#include "solver/io/run_directory.hpp"
#include "solver/run/any_step.hpp"
#include "solver/scene/initial_particles.hpp"
#include "solver/scene/scene_limits.hpp"
#include "solver/step/host/host_step.hpp"

namespace talus {

namespace {

std::string format_number(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", value);
  return text;
}

}  // namespace

namespace {

double clock_seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

std::string absolute_path(const std::string& path) {
  return std::filesystem::absolute(path.empty() ? "." : path).lexically_normal().string();
}

long long peak_resident_bytes() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<long long>(usage.ru_maxrss) * 1024;  // Linux: kilobytes
}

}  // namespace

std::unique_ptr<AnyStep> make_host_step(const Scene& scene, int threads) {
  if (scene.precision == Precision::float32) {
    return std::make_unique<StepAdapter<HostStep<float>>>(scene, "cpu", threads);
  }
  return std::make_unique<StepAdapter<HostStep<double>>>(scene, "cpu", threads);
}

struct ProductionRunner::Impl {
  const Scene& scene;
  ProductionSettings settings;
  // The output root, held for the run's whole life (run_directory.hpp; released after the
  // outputs close), and the run's id, which its checkpoints carry (a resumed run keeps its
  // checkpoint's).
  OutputLock lock;
  std::string run_id;
  // A resumed run's step is built from the scene without its initial particles (the checkpoint
  // replaces them; initial_particles.hpp), which must outlive the step.
  std::unique_ptr<Scene> resumed_scene;
  std::unique_ptr<AnyStep> step;
  int host_threads = 0;  // the host step's, 0 for another backend
  long long step_index = 0, total_steps = 0;
  std::unique_ptr<OutputSchedule> schedule;
  std::vector<std::string> outputs;
  double contacts_sum = 0, output_seconds = 0;
  double started = 0, last_progress = 0;
  // Checkpoints: their directory (empty: none asked for), this run's files there (by step; only
  // these are pruned), the files the scene reads and their fingerprints.
  std::string checkpoint_dir;
  std::vector<std::string> own_checkpoints;
  std::vector<std::string> input_files;
  std::vector<std::uint64_t> input_hashes;
  std::size_t initial_particles = 0;  // at step 0 (a resumed run's outputs are shaped by it)
  long long resumed_from = -1, last_checkpoint_step = -1;
  std::string last_checkpoint;
  bool interrupted = false;
  // The watchdog's reference: the energy held at the first check, the lowest gravitational
  // energy seen (what gravity has released at most), and the next step it looks.
  EnergyTerms first_energy;
  double lowest_gravitational = 0;
  long long next_watch = 0;
  // The steady part (ProductionReport::steady): the clock and the step's counters at the end of
  // this run's first step (steady_step -1: not reached yet), and the clock at the end of its
  // latest step (what report() computes for itself, e.g. the bed height, is not a step's).
  long long steady_step = -1;
  double last_step_clock = 0;
  double steady_clock = 0, steady_exchange = 0, steady_bytes = 0, steady_vote = 0,
         steady_rebuild = 0;
  StageSeconds steady_stages{};
  double setup_mark = 0;  // the clock at the end of the setup's last part (setup_done)
  void setup_part_done(const char* part) {
    const double now = clock_seconds();
    if (settings.setup_done) settings.setup_done(part, now - setup_mark);
    setup_mark = now;
  }

  Impl(const Scene& s, ProductionSettings set) : scene(s), settings(std::move(set)) {}

  // Stops the run (std::runtime_error) when its state is no longer finite, or when the energy it
  // holds exceeds by more than all it was ever given: what it held at the start, what gravity
  // released (its lowest gravitational energy so far), what moving walls and feeds put in.
  // Damping and friction only take energy out, so this is a law integrated with too large a step.
  void watch_energy() {
    const EnergyTerms e = step->energy();
    const bool first = next_watch == 0 || resumed_from == step_index - 1;
    next_watch = step_index + kEnergyWatchEvery;
    if (first && e.finite()) {
      first_energy = e;
      lowest_gravitational = e.gravitational;
      return;
    }
    const auto where = [&] {
      return scene.file + ": the run stopped at step " + std::to_string(step_index) +
             " (t = " + format_number(step->time()) + " s, " + std::to_string(step->particles()) +
             " particles): ";
    };
    if (!e.finite())
      throw std::runtime_error(where() +
                               "the particles' state is no longer finite (a position, velocity "
                               "or energy is inf or NaN); " +
                               settings.instability_hint);
    lowest_gravitational = std::min(lowest_gravitational, e.gravitational);
    const double given = first_energy.kinetic() + first_energy.elastic_normal +
                         first_energy.elastic_tangential +
                         (first_energy.gravitational - lowest_gravitational) +
                         std::abs(e.ledger.wall_work - first_energy.ledger.wall_work) +
                         (e.ledger.fed - first_energy.ledger.fed);
    // What removed particles took out is counted as held (their gravitational energy may be
    // negative: removing a particle that fell low raises the sum that stays).
    const double gained = e.mechanical() + (e.ledger.removed - first_energy.ledger.removed) -
                          first_energy.mechanical() -
                          (e.ledger.wall_work - first_energy.ledger.wall_work) -
                          (e.ledger.fed - first_energy.ledger.fed);
    // Far beyond: grown by more than all it was given (an exact run gains nothing; a tiny
    // absolute floor for a run at rest).
    if (gained > std::max(given, 1e-300))
      throw std::runtime_error(
          where() + "its energy grew by " + format_number(gained) + " J, more than the " +
          format_number(given) +
          " J that its start, gravity, moving walls and feeds gave it (kinetic energy now " +
          format_number(e.kinetic()) + " J): the contacts are creating energy. " +
          settings.instability_hint);
  }

  std::vector<double> probe_values() const {
    std::vector<double> values;
    for (const Probe probe : scene.outputs.probes->quantities) {
      switch (probe) {
        // Each rank's number over its own particles, combined over the domain's ranks.
        case Probe::kinetic_energy:
          values.push_back(step->domain().sum(step->kinetic_energy()));
          break;
        case Probe::contact_count:
          values.push_back(step->domain().sum(static_cast<double>(step->pair_contacts())));
          break;
        case Probe::bed_height:
          values.push_back(step->domain().max(step->bed_height(*scene.effects.gravity)));
          break;
        case Probe::energy: {
          const EnergyTerms e = step->energy();
          values.insert(values.end(),
                        {e.kinetic_translational, e.kinetic_rotational, e.gravitational,
                         e.elastic_normal, e.elastic_tangential, e.ledger.dissipated,
                         e.ledger.wall_work, e.ledger.fed, e.ledger.removed, e.balance()});
          break;
        }
        case Probe::wall_forces:
          for (std::size_t w = 0; w < scene.walls.size(); ++w) {
            const Vec3d f = step->wall_force(static_cast<int>(w));
            const Vec3d t = step->wall_torque(static_cast<int>(w));
            values.insert(values.end(), {f.x, f.y, f.z, t.x, t.y, t.z});
          }
          break;
      }
    }
    return values;
  }

  // The schedule's view of the step (output_schedule.hpp).
  struct Source : OutputSource {
    const Impl& m;
    explicit Source(const Impl& impl) : m(impl) {}
    double time() const override { return m.step->time(); }
    std::vector<TrajectoryRow> rows() const override { return m.step->rows(); }
    std::vector<double> probe_values() const override { return m.probe_values(); }
  };

  void write_outputs(bool last) {
    if (!schedule->due(step_index, last)) return;
    const double start = clock_seconds();
    schedule->write(step_index, last, Source(*this));
    output_seconds += clock_seconds() - start;
  }

  // The run's state at this step (step, outputs, what resuming needs to find the run again),
  // through a temporary name and a rename, once every output file it counts is on the disk;
  // then all but the newest `keep` of this run's checkpoints are removed (another run's never).
  void write_checkpoint_now() {
    const double start = clock_seconds();
    schedule->sync();
    Checkpoint c;
    const std::filesystem::path root = absolute_path(settings.output_root);
    c.put_text("run.id", run_id);  // first: checkpoint_run_id reads only the first sections
    c.put_text("run.scene_file", input_files.front());
    c.put_value("run.scene_hash", input_hashes.front());
    std::string files;
    for (const std::string& file : input_files) files += file + "\n";
    c.put_text("run.input_files", files);
    c.put("run.input_hashes", input_hashes);
    c.put_text("run.output_root",
               root.lexically_relative(absolute_path(checkpoint_dir)).generic_string());
    c.put_text("run.backend", step->backend());
    c.put_text("run.precision", to_string(scene.precision));
    c.put_value("run.total_steps", total_steps);
    c.put_value("run.contacts_sum", contacts_sum);
    schedule->save(c);
    step->save_state(c);
    const std::string path = checkpoint_dir + "/" + checkpoint_file_name(step_index);
    write_checkpoint(path, c);
    last_checkpoint = path;
    last_checkpoint_step = step_index;
    if (std::find(own_checkpoints.begin(), own_checkpoints.end(), path) == own_checkpoints.end())
      own_checkpoints.push_back(path);
    // By step: the names hold the step in at least 9 digits, so shorter names come first.
    std::sort(own_checkpoints.begin(), own_checkpoints.end(),
              [](const std::string& a, const std::string& b) {
                return a.size() != b.size() ? a.size() < b.size() : a < b;
              });
    const std::size_t keep = static_cast<std::size_t>(scene.outputs.checkpoint->keep);
    while (own_checkpoints.size() > keep) {
      std::error_code ignored;  // one already gone is no reason to stop the run
      std::filesystem::remove(own_checkpoints.front(), ignored);
      own_checkpoints.erase(own_checkpoints.begin());
    }
    output_seconds += clock_seconds() - start;
  }
};

ProductionRunner::ProductionRunner(const Scene& scene, ProductionSettings settings)
    : impl_(std::make_unique<Impl>(scene, std::move(settings))) {
  Impl& m = *impl_;
  m.started = m.last_progress = m.setup_mark = clock_seconds();
  if (scene.outputs.probes) {
    for (const Probe probe : scene.outputs.probes->quantities) {
      if (probe == Probe::bed_height && !scene.effects.gravity) {
        throw std::runtime_error(scene.file + ": outputs.probes: bed_height needs gravity");
      }
    }
  }
  const Checkpoint* resume = m.settings.resume.get();
  m.run_id = resume && resume->has("run.id") ? resume->text("run.id") : new_run_id();
  m.lock = claim_output_root(scene, m.settings.output_root, m.run_id, resume != nullptr,
                             m.settings.overwrite);
  if (resume) m.resumed_scene = std::make_unique<Scene>(without_initial_particles(scene));
  const Scene& step_scene = resume ? *m.resumed_scene : scene;
  if (m.settings.make_step) {
    m.step = m.settings.make_step(step_scene);
  } else {
    m.host_threads = host_thread_count(m.settings.host_threads);
    m.step = make_host_step(step_scene, m.host_threads);
  }
  m.setup_part_done("step");
  m.total_steps = scene_step_count(scene);  // at most kMaxSteps (the loader refused more)
  m.initial_particles = resume ? initial_particle_count(scene) : m.step->particles();
  if (resume) {
    if (resume->text("run.precision") != to_string(scene.precision))
      resume->fail("run.precision", "written in " + resume->text("run.precision") +
                                        " precision, the run asks for " +
                                        to_string(scene.precision));
    m.step->restore_state(*resume);
    m.step_index = resume->get_value<long long>("step.steps");
    m.contacts_sum = resume->get_value<double>("run.contacts_sum");
    m.resumed_from = m.step_index;
    m.setup_part_done("restore");
  }
  if (scene.outputs.checkpoint) {
    m.checkpoint_dir = joined_path(m.settings.output_root, scene.outputs.checkpoint->directory);
    create_output_directory(m.checkpoint_dir,
                            "checkpoint directory (outputs.checkpoint.directory)");
    // Resuming checks that the scene and its meshes are unchanged.
    m.input_files = scene_input_files(scene);
    for (const std::string& file : m.input_files) m.input_hashes.push_back(file_hash(file));
    if (resume)
      for (const std::string& path : list_checkpoints(m.checkpoint_dir))
        if (checkpoint_run_id(path) == m.run_id) m.own_checkpoints.push_back(path);
    m.outputs.push_back(m.checkpoint_dir);
  }
  m.schedule = std::make_unique<OutputSchedule>(scene, m.settings.output_root, "talus",
                                                m.initial_particles, resume);
  for (const std::string& path : m.schedule->paths()) m.outputs.push_back(path);
  if (resume) {
    // The checkpoint's step has its outputs already. A restored step holds no contacts until it
    // evaluates forces (its elastic energy reads zero), so the watchdog's reference is the first
    // step after the checkpoint's: a settled bed's stored energy is not taken for energy created.
    m.next_watch = m.step_index + 1;
    return;
  }
  m.step->evaluate_forces();  // step 0's contacts
  m.watch_energy();
  m.write_outputs(done());
  m.setup_part_done("first_forces");
}

ProductionRunner::~ProductionRunner() = default;

bool ProductionRunner::done() const {
  return impl_->step_index >= impl_->total_steps;
}
long long ProductionRunner::step() const {
  return impl_->step_index;
}
const StepPlan& ProductionRunner::plan() const {
  return impl_->step->plan();
}
std::vector<TrajectoryRow> ProductionRunner::rows() const {
  return impl_->step->rows();
}
std::size_t ProductionRunner::pair_contacts() const {
  return impl_->step->pair_contacts();
}
std::size_t ProductionRunner::wall_contacts() const {
  return impl_->step->wall_contacts();
}

void ProductionRunner::advance() {
  Impl& m = *impl_;
  if (done()) return;
  m.step->step();
  ++m.step_index;
  m.contacts_sum += static_cast<double>(m.step->pair_contacts() + m.step->wall_contacts());
  if (m.step_index >= m.next_watch || done()) m.watch_energy();
  m.write_outputs(done());
  if (!m.checkpoint_dir.empty() && m.step_index % m.scene.outputs.checkpoint->every == 0 && !done())
    m.write_checkpoint_now();
  const double now = clock_seconds();
  m.last_step_clock = now;
  if (m.steady_step < 0) {  // the first step of this run: what follows is steady
    m.steady_step = m.step_index;
    m.steady_clock = now;
    m.steady_stages = m.step->stage_seconds();
    m.steady_exchange = m.step->exchange_seconds();  // decomposed: a collective, once
    m.steady_vote = m.step->exchange_vote_seconds();
    m.steady_rebuild = m.step->exchange_rebuild_seconds();
    m.steady_bytes = m.step->exchange_bytes();
  }
  if (now - m.last_progress >= m.settings.progress_interval) {
    report_progress();
    m.last_progress = now;
  }
}

void ProductionRunner::interrupt() {
  Impl& m = *impl_;
  m.interrupted = true;
  if (!m.checkpoint_dir.empty() && m.last_checkpoint_step != m.step_index &&
      m.resumed_from != m.step_index)
    m.write_checkpoint_now();
}

bool ProductionRunner::interrupted() const {
  return impl_->interrupted;
}

void ProductionRunner::report_progress() {
  const Impl& m = *impl_;
  if (!m.settings.progress) return;
  ProductionProgress p;
  p.step = m.step_index;
  p.total_steps = m.total_steps;
  p.time = m.step->time();
  p.end_time = m.scene.end_time;
  p.particles = m.step->particles();
  p.contacts = m.step->pair_contacts() + m.step->wall_contacts();
  p.wall_seconds = clock_seconds() - m.started;
  p.feeds = m.step->feed_counts();
  m.settings.progress(p);
}

ProductionReport ProductionRunner::report() const {
  const Impl& m = *impl_;
  ProductionReport r;
  r.backend = m.step->backend();
  r.host_threads = m.host_threads;
  r.steps = m.step_index;
  r.simulated_time = m.step->time();
  r.wall_seconds = clock_seconds() - m.started;
  r.particles = m.step->particles();
  r.removed_particles = m.step->removed_particles();
  r.mean_contacts = m.step_index > 0 ? m.contacts_sum / double(m.step_index) : 0;
  r.pair_list_builds = m.step->pair_list_builds();
  for (const Stage stage : m.step->plan().stages) {
    r.stage_seconds.emplace_back(to_string(stage),
                                 m.step->stage_seconds()[static_cast<int>(stage)]);
  }
  r.output_seconds = m.output_seconds;
  r.particle_bytes = m.step->bytes();
  r.exchange_seconds = m.step->exchange_seconds();
  r.exchange_vote_seconds = m.step->exchange_vote_seconds();
  r.exchange_rebuild_seconds = m.step->exchange_rebuild_seconds();
  r.exchange_bytes = m.step->exchange_bytes();
  r.rebalances = m.step->rebalances();
  const AnyStep::GraphSteps graphs = m.step->graph_steps();
  r.graph_steps = graphs.steps;
  r.graph_captures = graphs.captures;
  r.graph_aborted = graphs.aborted;
  r.stages_beside = m.step->stages_beside();
  r.feeds = m.step->feed_counts();
  r.peak_memory_bytes = peak_resident_bytes();
  r.outputs = m.outputs;
  if (m.scene.effects.gravity) r.bed_height = m.step->bed_height(*m.scene.effects.gravity);
  if (m.steady_step >= 0 && m.step_index > m.steady_step) {
    ProductionReport::Steady& s = r.steady;
    s.steps = m.step_index - m.steady_step;
    s.seconds = m.last_step_clock - m.steady_clock;
    for (const Stage stage : m.step->plan().stages) {
      const int k = static_cast<int>(stage);
      s.stage_seconds.emplace_back(to_string(stage),
                                   m.step->stage_seconds()[k] - m.steady_stages[k]);
    }
    s.exchange_seconds = r.exchange_seconds - m.steady_exchange;
    s.exchange_bytes = r.exchange_bytes - m.steady_bytes;
    s.exchange_vote_seconds = r.exchange_vote_seconds - m.steady_vote;
    s.exchange_rebuild_seconds = r.exchange_rebuild_seconds - m.steady_rebuild;
  }
  r.resumed_from_step = m.resumed_from;
  r.interrupted = m.interrupted;
  r.last_checkpoint = m.last_checkpoint;
  return r;
}

ProductionReport run_production(const Scene& scene, const ProductionSettings& settings) {
  ProductionRunner runner(scene, settings);
  while (!runner.done()) {
    if (settings.stop_requested && settings.stop_requested()) {
      runner.interrupt();
      break;
    }
    runner.advance();
  }
  runner.report_progress();
  return runner.report();
}

std::vector<std::string> scene_input_files(const Scene& scene) {
  std::vector<std::string> files{absolute_path(scene.file)};
  const auto add = [&](const std::string& file) {
    const std::string path = absolute_path(file);
    if (std::find(files.begin(), files.end(), path) == files.end()) files.push_back(path);
  };
  for (const ParticleTemplate& t : scene.templates)
    if (!t.mesh_file.empty()) add(t.mesh_file);
  for (const WallSpec& wall : scene.walls)
    if (const auto* mesh = std::get_if<MeshWall>(&wall.shape)) add(mesh->file);
  return files;
}

namespace {

// Throws CheckpointError unless each file the checkpoint's run read still has its hash.
void check_input_files(const Checkpoint& checkpoint) {
  const std::string path = checkpoint.path();
  std::vector<std::string> files;
  std::vector<std::uint64_t> hashes;
  if (checkpoint.has("run.input_files")) {
    const std::string text = checkpoint.text("run.input_files");
    for (std::size_t begin = 0, end; (end = text.find('\n', begin)) != std::string::npos;
         begin = end + 1)
      files.push_back(text.substr(begin, end - begin));
    hashes = checkpoint.get<std::uint64_t>("run.input_hashes");
    if (files.empty() || hashes.size() != files.size())
      checkpoint.fail("run.input_hashes", "expected one hash per file of run.input_files");
  } else {  // a checkpoint of an older talus: the scene file only
    files = {checkpoint.text("run.scene_file")};
    hashes = {checkpoint.get_value<std::uint64_t>("run.scene_hash")};
  }
  for (std::size_t k = 0; k < files.size(); ++k) {
    const std::string what =
        k == 0 ? "the run's scene file '" + files[k] + "'" : "the mesh file '" + files[k] + "'";
    std::uint64_t now = 0;
    try {
      now = file_hash(files[k]);
    } catch (const CheckpointError&) {
      std::string problem = input_file_problem(files[k]);
      if (problem.empty()) problem = "cannot be read";
      throw CheckpointError(path + ": " + what + (k == 0 ? "" : ", which the scene reads,") + " " +
                            problem + "; restore it, or start a new run");
    }
    if (now != hashes[k])
      throw CheckpointError(path + ": " + what + (k == 0 ? "" : ", which the scene reads,") +
                            " has changed since the checkpoint was written (its hash differs); "
                            "restore it, or start a new run");
  }
}

}  // namespace

ResumePoint read_resume_point(const std::string& path) {
  std::error_code error;
  const bool one_file = std::filesystem::is_regular_file(path, error);
  const std::string directory =
      one_file ? std::filesystem::path(absolute_path(path)).parent_path().string() : path;
  if (!one_file && !std::filesystem::is_directory(path, error)) {
    const std::string problem = input_file_problem(path);  // what it is instead
    throw CheckpointError(
        path + ": " +
        (problem == "does not exist"
             ? "no such checkpoint file or directory"
             : "neither a checkpoint file nor a directory of checkpoints: it " + problem));
  }
  const std::vector<std::string> files =
      one_file ? std::vector<std::string>{path} : list_checkpoints(directory);
  if (files.empty()) {
    // A checkpoint's name on something that is not a file (list_checkpoints skips it).
    std::error_code ignored;
    for (const auto& entry : std::filesystem::directory_iterator(directory, ignored)) {
      const std::string name = entry.path().filename().string();
      if (name.rfind("checkpoint_", 0) == 0 && name.size() > 15 &&
          name.compare(name.size() - 4, 4, ".bin") == 0)
        throw CheckpointError(entry.path().string() + ": cannot resume from it: it " +
                              input_file_problem(entry.path().string()));
    }
    // The run's output root given instead of its checkpoint directory (the default name).
    const std::string inside = (std::filesystem::path(directory) / "checkpoints").string();
    const std::string hint = list_checkpoints(inside).empty()
                                 ? ""
                                 : "; " + inside +
                                       " holds checkpoints: continue with 'talus run --resume " +
                                       inside + "'";
    throw CheckpointError(directory +
                          ": no checkpoint to resume from (checkpoint_<step>.bin; a "
                          "run writes them when its scene has outputs.checkpoint)" +
                          hint);
  }
  ResumePoint r;
  r.checkpoint_path = files.back();
  std::shared_ptr<Checkpoint> checkpoint;
  try {
    checkpoint = std::make_shared<Checkpoint>(read_checkpoint(r.checkpoint_path));
  } catch (const CheckpointError& e) {
    if (files.size() < 2) throw;
    throw CheckpointError(std::string(e.what()) +
                          "; an older checkpoint is there: continue from it with 'talus run "
                          "--resume " +
                          files[files.size() - 2] + "'");
  }
  r.scene_file = checkpoint->text("run.scene_file");
  check_input_files(*checkpoint);
  r.output_root =
      (std::filesystem::path(absolute_path(directory)) / checkpoint->text("run.output_root"))
          .lexically_normal()
          .string();
  if (r.output_root.size() > 1 && r.output_root.back() == '/') r.output_root.pop_back();
  r.backend = checkpoint->text("run.backend");
  r.precision = checkpoint->text("run.precision");
  r.step = checkpoint->get_value<long long>("step.steps");
  r.checkpoint = std::move(checkpoint);
  return r;
}

}  // namespace talus
