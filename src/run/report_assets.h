// The run report's page and the library it draws with, built into the library from web/ by
// cmake/embed_text.cmake (src/CMakeLists.txt): "report.html" (the page, with marked lines
// for the writer to fill), "report.js" (its script), "three.module.min.js" and
// "OrbitControls.js" (three.js, from web/node_modules, which scripts/install-deps.sh installs
// with npm ci from web/package-lock.json).
#pragma once

#include <string_view>

namespace clothsim {

// The named asset's text, or an empty view for a name that was not built in.
std::string_view report_asset(std::string_view name);

}  // namespace clothsim
