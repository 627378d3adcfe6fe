// The `talus` command (its arguments: command_line.hpp). Results go to stdout as one JSON
// document; a bad argument goes to stderr as one line naming it, followed by the command's usage
// line, with exit status 2.
#include <cstdio>
#include <exception>
#include <new>
#include <string>
#include <vector>

#include "solver/app/arguments.hpp"
#include "solver/app/command_line.hpp"
#include "solver/app/commands.hpp"
#include "solver/app/message_text.hpp"
#include "solver/io/output_files.hpp"
#include "solver/parallel/decomposed_step.hpp"
#if TALUS_HAVE_MPI
#include "solver/parallel/mpi_communicator.hpp"
#endif
#include "solver/scene/scene_loader.hpp"
#include "validation/framework/validation.hpp"

namespace {

constexpr int kExitUsage = 2;
constexpr int kExitFailure = 1;

int run(const std::vector<std::string>& args) {
  const talus::ParsedCommand command = talus::parse_command_line(args);
  if (command.bare) {
    std::fprintf(stderr,
                 "talus: no command given: 'talus run' ('talus --help' lists the "
                 "commands)\n");
  }
  if (talus::world()->size() > 1 && command.kind != talus::ParsedCommand::run)
    throw talus::RunError("only 'talus run' runs on several ranks (mpirun -np " +
                          std::to_string(talus::world()->size()) +
                          "); run this command in one process");
  std::string json;
  switch (command.kind) {
    case talus::ParsedCommand::help:
      std::fputs(command.help_text.c_str(), stdout);
      return 0;
    case talus::ParsedCommand::overlap: {
      const std::vector<std::string>& o = command.operands;
      json = talus::overlap_json(o[0], o[1], o[2], o[3]);
      break;
    }
    case talus::ParsedCommand::shape:
      json = talus::shape_json(command.operands[0]);
      break;
    case talus::ParsedCommand::run:
      json = talus::run_json(command.run_arguments);
      break;
    case talus::ParsedCommand::render:
      json = talus::render_json(command.render_arguments);
      break;
    case talus::ParsedCommand::accuracy:
      json = talus::accuracy_json(command.accuracy_arguments);
      break;
    case talus::ParsedCommand::validate: {
      bool passed = false;
      json = talus::validate_json(command.validate_arguments, passed);
      std::fputs(json.c_str(), stdout);
      return passed ? 0 : kExitFailure;  // a case failed: its results are written all the same
    }
  }
  std::fputs(json.c_str(), stdout);
  return 0;
}

}  // namespace

int run_and_report(const std::vector<std::string>& args);

int main(int argc, char** argv) {
  const std::vector<std::string> args(argv + 1, argv + argc);
#if TALUS_HAVE_MPI
  // Started by mpirun: MPI for the run's ranks (docs/parallel.md); rank 0 alone speaks, and every
  // rank ends the decomposed run before it leaves, whatever went wrong, so that none waits.
  const talus::MpiSession mpi;
  talus::set_world(mpi.world());
  if (mpi.rank() != 0 && !std::freopen("/dev/null", "w", stderr)) return kExitFailure;
#endif
  const int status = run_and_report(args);
  talus::end_decomposed_run(*talus::world());
  return status;
}

int run_and_report(const std::vector<std::string>& args) {
  try {
    const int status = run(args);
    if (std::fflush(stdout) != 0) {
      std::fprintf(stderr, "talus: error: could not write the output\n");
      return kExitFailure;
    }
    return status;
  } catch (const talus::UsageError& error) {
    std::fprintf(stderr, "talus: error: %s\n%s", talus::printable_message(error.what()).c_str(),
                 talus::usage_line(args).c_str());
    return kExitUsage;
  } catch (const talus::SceneError& error) {
    std::fprintf(stderr, "talus: error: %s\n", talus::printable_message(error.what()).c_str());
    return kExitUsage;
  } catch (const talus::RunInterrupted& error) {
    if (!error.summary().empty()) {
      std::fputs(error.summary().c_str(), stdout);
      std::fflush(stdout);
    }
    std::fprintf(stderr, "talus: %s\n", talus::printable_message(error.what()).c_str());
    return error.exit_status();
  } catch (const talus::validation::ValidationError& error) {
    // An unknown case or a bad expected.yaml: named before any case runs.
    std::fprintf(stderr, "talus: error: %s\n", talus::printable_message(error.what()).c_str());
    return kExitUsage;
  } catch (const talus::RunError& error) {
    std::fprintf(stderr, "talus: error: %s\n", talus::printable_message(error.what()).c_str());
    return kExitUsage;
  } catch (const talus::OutputPathError& error) {
    // An output path the user gave that cannot be used (a file where a directory must go).
    std::fprintf(stderr, "talus: error: %s\n", talus::printable_message(error.what()).c_str());
    return kExitUsage;
  } catch (const std::bad_alloc&) {
    // What the scene's memory estimate (scene/scene_memory.hpp) let through: one line, not an
    // abort, and nothing else is allocated to say it.
    std::fputs(
        "talus: error: out of memory: an allocation failed; the run needs more "
        "memory than this process may use (the machine's, or a limit such as ulimit -v); run "
        "fewer particles\n",
        stderr);
    return kExitFailure;
  } catch (const std::exception& error) {
    // Not the user's arguments: an internal failure (e.g. out of memory).
    std::fprintf(stderr, "talus: error: %s\n", talus::printable_message(error.what()).c_str());
    return kExitFailure;
  }
}
