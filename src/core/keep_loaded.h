// Keeps shared libraries that are loaded now loaded until the process exits, for sanitizer builds
// (docs/testing.md, "What CI runs"): a graphics driver that its loader unloads early (GLX when the
// display closes, the Vulkan loader when the last instance goes) leaves heap blocks its static
// data pointed to, which LeakSanitizer at exit then reports as leaked from "<unknown module>",
// a name no suppression can match. Pinned, the blocks stay reachable, as in any process that keeps
// its driver.
#pragma once

#include <functional>
#include <string_view>

namespace clothsim {

// Pins (dlopen with RTLD_NODELETE) every loaded library whose path `matches`.
void keep_libraries_loaded(const std::function<bool(std::string_view path)>& matches);

}  // namespace clothsim
