// clothsim: the command-line tool. main() only parses and dispatches; each subcommand is one
// file (commands.h) and the shared exit codes and error reporting are in cli_support.h.
#include <cstdio>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "cli_support.h"
#include "commands.h"

namespace {

std::string main_footer() {
  std::string text =
      "Examples:\n"
      "  clothsim scenes                                   # the built-in scenes\n"
      "  clothsim run paper-fig4                           # writes out/paper-fig4/\n"
      "  clothsim run --paper-args 21,21,1,4,1,1400,200,80,5,1 --duration 10\n"
      "  clothsim run my-scene.json --until-rest --out out/mine\n"
      "  clothsim validate my-scene.json\n"
#if defined(CLOTHSIM_HAS_VIEWER)
      "  clothsim view paper-fig4                          # the interactive viewer\n"
#endif
      "  clothsim params | grep stiffness                  # keys for --set\n"
      "  clothsim bench --quick                            # throughput on this machine\n"
      "  clothsim sweep paper-fig5 --param output.fps=30,60 --out out/sweep   # a grid of runs\n"
      "  clothsim devices                                  # the Vulkan devices (docs/gpu.md)\n"
      "  clothsim run --help                               # every flag of a subcommand\n"
      "\n";
  text += clothsim::cli::exit_code_help();
  text += "\n\nDocumentation: docs/cli.md (this tool), docs/scene-format.md (scene files).";
  return text;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace clothsim::cli;
  const Invocation invocation{join_command_line(argc, argv)};

  CLI::App app{"clothsim: thin-sheet simulation on a mass-spring lattice with radial (angular) springs", "clothsim"};
  app.set_version_flag("--version", "clothsim " CLOTHSIM_VERSION);
  app.require_subcommand(1);
  app.get_formatter()->column_width(34);
  app.footer(main_footer());
  std::vector<Subcommand> commands = {
      add_run_command(app, invocation), add_validate_command(app), add_scenes_command(app),  add_params_command(app),
      add_bench_command(app),           add_sweep_command(app),    add_devices_command(app), add_report_command(app)};
#if defined(CLOTHSIM_HAS_VIEWER)
  commands.push_back(add_view_command(app));
#endif

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    // --help and --version arrive as "errors" with exit code 0.
    if (error.get_exit_code() == static_cast<int>(CLI::ExitCodes::Success)) return app.exit(error);
    print_error(error.what());
    const std::vector<CLI::App*> selected = app.get_subcommands();
    std::string usage = "clothsim";
    if (!selected.empty()) {
      usage += ' ';
      usage += selected.front()->get_name();
    }
    std::fprintf(stderr, "Run '%s --help' for usage.\n", usage.c_str());
    return kExitBadInput;
  }
  for (const Subcommand& command : commands) {
    if (command.app->parsed()) return run_subcommand(command.run);
  }
  return kExitBadInput;  // unreachable: require_subcommand(1)
}
