// The `talus` command line, defined once with CLI11: the commands (run, render, validate,
// accuracy, overlap, shape, help), their options and the generated help. Parsing is apart from
// running, so that every bad argument is a UsageError naming it and what was expected before any
// file is read.
#pragma once

#include <string>
#include <vector>

#include "solver/app/render_arguments.hpp"
#include "solver/app/run_arguments.hpp"
#include "solver/app/validate_arguments.hpp"

namespace talus {

struct ParsedCommand {
  // `talus` alone is `run` with no options (the built-in scene); `help` also stands for
  // `--help`, `-h` and `COMMAND --help`, with the text to print in `help_text`.
  enum Kind { run, render, validate, accuracy, overlap, shape, help } kind = run;
  bool bare = false;                     // `talus` with no argument at all
  RunArguments run_arguments;            // kind run
  RenderArguments render_arguments;      // kind render
  ValidateArguments validate_arguments;  // kind validate
  AccuracyArguments accuracy_arguments;  // kind accuracy
  std::vector<std::string> operands;     // kind overlap (A POSE_A B POSE_B) or shape (A)
  std::string help_text;                 // kind help: the generated help, newline-terminated
};

// The arguments after the program's name. Throws UsageError: the message names the argument and
// what was expected; usage_line() is the synopsis of the command it concerns.
ParsedCommand parse_command_line(const std::vector<std::string>& arguments);

// "usage: talus run [options] [SCENE.yaml] ('talus run --help' lists the options)", for the
// command named first in `arguments` when it is one, else the list of commands.
std::string usage_line(const std::vector<std::string>& arguments);

}  // namespace talus
