// The picture flags of `clothsim run`: --render, --size, --camera, --mesh, --show and --samples,
// registered on the command line. What they mean and how they are checked is the library's
// (run/render_plan.h); the recorder that renders each output frame is run/run_recorder.h.
#pragma once

#include <CLI/CLI.hpp>

#include "run/render_plan.h"

namespace clothsim::cli {

// Registers the flags on `app`, writing into `flags` (whose defaults are the library's).
void add_render_flags(CLI::App& app, RenderFlags& flags);

}  // namespace clothsim::cli
