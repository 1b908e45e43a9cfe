// The subcommands of the clothsim tool, one file each, all of the same shape (cli_support.h).
#pragma once

#include <CLI/CLI.hpp>

#include "cli_support.h"

namespace clothsim::cli {

Subcommand add_run_command(CLI::App& parent, const Invocation& invocation);  // run_command.cpp
Subcommand add_validate_command(CLI::App& parent);                           // validate_command.cpp
Subcommand add_scenes_command(CLI::App& parent);                             // catalog_commands.cpp
Subcommand add_params_command(CLI::App& parent);                             // catalog_commands.cpp
Subcommand add_bench_command(CLI::App& parent);                              // bench_command.cpp
Subcommand add_sweep_command(CLI::App& parent);                              // sweep_command.cpp
Subcommand add_devices_command(CLI::App& parent);                            // devices_command.cpp
Subcommand add_report_command(CLI::App& parent);                             // report_command.cpp
// Built with CLOTHSIM_BUILD_RENDER (it needs OpenGL, GLFW and Dear ImGui); CLOTHSIM_HAS_VIEWER.
Subcommand add_view_command(CLI::App& parent);  // view_command.cpp

}  // namespace clothsim::cli
