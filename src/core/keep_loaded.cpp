#include "core/keep_loaded.h"

#include <dlfcn.h>
#include <link.h>

#include <string>
#include <vector>

namespace clothsim {

void keep_libraries_loaded(const std::function<bool(std::string_view path)>& matches) {
  struct Search {
    const std::function<bool(std::string_view)>& matches;
    std::vector<std::string> found;
  } search{matches, {}};
  dl_iterate_phdr(
      [](dl_phdr_info* info, std::size_t, void* data) {
        auto& state = *static_cast<Search*>(data);
        const std::string_view name = info->dlpi_name != nullptr ? info->dlpi_name : "";
        if (!name.empty() && state.matches(name)) state.found.emplace_back(name);
        return 0;
      },
      &search);
  for (const std::string& library : search.found) dlopen(library.c_str(), RTLD_NOW | RTLD_NOLOAD | RTLD_NODELETE);
}

}  // namespace clothsim
