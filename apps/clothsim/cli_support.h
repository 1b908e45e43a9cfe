// What every clothsim subcommand shares: exit codes, error reporting, and the one-line
// descriptions of scenes and lattices.
//
// Each subcommand lives in its own file with the same shape (STYLE.md rule 16): an
// add_<name>_command() that registers the subcommand and its options on the CLI11 app and returns
// a Subcommand whose `run` does the work after parsing and returns the exit code. main.cpp only
// parses and dispatches. Errors reach the user through exceptions caught in one place
// (run_subcommand): InputError -> exit 2, OutputError -> exit 3, each printed as
// "clothsim: error: <message>" on stderr.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <string_view>

#include <CLI/CLI.hpp>

#include "model/cloth_model.h"
#include "scene/scene.h"

namespace clothsim::cli {

// Exit codes, documented in docs/cli.md and in the --help footer.
enum ExitCode : int {
  kExitSuccess = 0,           // the command did its work (a run completed or came to rest)
  kExitSimulationFailed = 1,  // the simulation stopped with a diagnosis; its output is kept
  kExitBadInput = 2,          // a scene, flag or value was rejected; nothing was written
  kExitOutputError = 3,       // the output could not be written
  kExitInterrupted = 130,     // stopped by SIGINT (128 + 2, the shell's convention)
};

// The program as invoked, for summary.json.
struct Invocation {
  std::string command_line;  // argv joined, with shell quoting where needed
};

struct Subcommand {
  CLI::App* app = nullptr;
  std::function<int()> run;
};

// The footer of `clothsim --help` and the exit-code lines every subcommand's footer ends with.
std::string exit_code_help();

// Runs a subcommand's work and turns the exceptions that reach it into messages and exit codes.
int run_subcommand(const std::function<int()>& run);

// "clothsim: error: <message>" on stderr.
void print_error(std::string_view message);

// Quotes `argv` into one line a POSIX shell would split back into the same words.
std::string join_command_line(int argc, const char* const* argv);

// "1 anchor", "2 anchors".
std::string count_noun(std::uint64_t count, std::string_view singular, std::string_view plural);

// "21x21 lattice, 441 particles, 840 connectors, 3200 radial springs, 1 anchor".
std::string describe_lattice(const ClothModel& model);

// "rkf45, 20 s at 60 fps", "rk4, until rest (at most 3600 s) at 60 fps".
std::string describe_run_settings(const SceneSpec& spec);

// A number as short as it reads back: "0.5", "1e-6", "20".
std::string format_number_short(double value);

// Wall-clock duration as "0.42 s", "12.3 s", "4 min 05 s", "2 h 03 min".
std::string format_duration(double seconds);

// Wraps `text` at `width` columns for printing after an `indent`-column prefix; continuation
// lines are indented by `indent` spaces.
std::string wrap_text(std::string_view text, std::size_t width, std::size_t indent);

}  // namespace clothsim::cli
