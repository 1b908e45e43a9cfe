#include "core/available_memory.h"

#include <sys/resource.h>

#include <algorithm>
#include <charconv>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <mutex>
#include <sstream>

namespace clothsim {
namespace {

namespace fs = std::filesystem;

// Limits at or above this are "no limit" (cgroup v1 writes 2^63 rounded down to a page).
constexpr std::size_t kUnlimited = std::size_t{1} << 60;

std::string read_text(const fs::path& path) {
  std::ifstream file(path);
  if (!file) return {};
  std::ostringstream text;
  text << file.rdbuf();
  return text.str();
}

std::size_t parse_number(std::string_view text) {
  while (!text.empty() && (text.front() == ' ' || text.front() == '\t')) text.remove_prefix(1);
  std::size_t value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  return error == std::errc{} && end != text.data() ? value : 0;
}

// The value of a "Key:   1234 kB" line of /proc files, in bytes; 0 if absent.
std::size_t status_field_bytes(std::string_view text, std::string_view key) {
  std::size_t at = 0;
  while (at < text.size()) {
    const std::size_t end = std::min(text.find('\n', at), text.size());
    const std::string_view line = text.substr(at, end - at);
    if (line.size() > key.size() && line.substr(0, key.size()) == key && line[key.size()] == ':') {
      const std::string_view value = line.substr(key.size() + 1);
      const std::size_t number = parse_number(value);
      return value.find("kB") != std::string_view::npos ? number * 1024 : number;
    }
    at = end + 1;
  }
  return 0;
}

void consider(AvailableMemory& least, std::size_t bytes, std::string source) {
  if (!least.known() || bytes < least.bytes) {
    least.bytes = bytes;
    least.source = std::move(source);
  }
}

// limit - usage of one cgroup folder, where it has a limit.
void consider_cgroup(AvailableMemory& least, const fs::path& folder, std::string_view limit_file,
                     std::string_view usage_file) {
  const std::size_t limit = cgroup_value_bytes(read_text(folder / limit_file));
  if (limit == 0 || limit >= kUnlimited) return;
  const std::size_t usage = cgroup_value_bytes(read_text(folder / usage_file));
  std::string source = "the cgroup limit (";
  source += (folder / limit_file).string();
  source += ")";
  consider(least, limit > usage ? limit - usage : 0, std::move(source));
}

// This process's cgroup and the groups above it, v2 and v1 layouts, where the folders exist.
// Inside a container the group path of /proc/self/cgroup may not exist under /sys/fs/cgroup
// (its root is the container's own group): the root folders are read too.
void consider_cgroups(AvailableMemory& least) {
  std::istringstream lines(read_text("/proc/self/cgroup"));
  std::string line;
  while (std::getline(lines, line)) {
    // "hierarchy-id:controllers:path"
    const std::size_t first = line.find(':');
    const std::size_t second = first == std::string::npos ? first : line.find(':', first + 1);
    if (second == std::string::npos) continue;
    const std::string controllers = line.substr(first + 1, second - first - 1);
    fs::path group = line.substr(second + 1);
    fs::path root;
    std::string_view limit_file;
    std::string_view usage_file;
    if (controllers.empty()) {
      root = "/sys/fs/cgroup";
      limit_file = "memory.max";
      usage_file = "memory.current";
    } else if (controllers == "memory" || controllers.find("memory,") != std::string::npos ||
               controllers.find(",memory") != std::string::npos) {
      root = "/sys/fs/cgroup/memory";
      limit_file = "memory.limit_in_bytes";
      usage_file = "memory.usage_in_bytes";
    } else {
      continue;
    }
    std::error_code error;
    for (fs::path at = group; !at.empty() && at != at.root_path(); at = at.parent_path()) {
      const fs::path folder = root / at.relative_path();
      if (fs::is_directory(folder, error)) consider_cgroup(least, folder, limit_file, usage_file);
    }
    consider_cgroup(least, root, limit_file, usage_file);
  }
}

// The soft limit this process set itself (cap_data_growth), and the name of the limit it restates.
struct OwnLimit {
  std::mutex mutex;
  int resource = -1;
  rlim_t value = RLIM_INFINITY;
  std::string source;
};

OwnLimit& own_limit() {
  static OwnLimit own;
  return own;
}

// What a limit of `value` on `resource` is called: `name`, unless this process set it.
std::string limit_name(int resource, rlim_t value, std::string name) {
  OwnLimit& own = own_limit();
  const std::lock_guard lock(own.mutex);
  if (resource == own.resource && value == own.value) return own.source;
  return name;
}

void consider_rlimit(AvailableMemory& least, int resource, std::string_view status, std::string_view used_key,
                     std::string name) {
  rlimit limit{};
  if (getrlimit(resource, &limit) != 0 || limit.rlim_cur == RLIM_INFINITY) return;
  std::string source = limit_name(resource, limit.rlim_cur, std::move(name));
  const auto cap = static_cast<std::size_t>(limit.rlim_cur);
  const std::size_t used = status_field_bytes(status, used_key);
  consider(least, cap > used ? cap - used : 0, std::move(source));
}

}  // namespace

std::size_t meminfo_available_bytes(std::string_view meminfo) { return status_field_bytes(meminfo, "MemAvailable"); }

std::size_t cgroup_value_bytes(std::string_view text) {
  while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.remove_suffix(1);
  if (text == "max") return 0;
  return parse_number(text);
}

AvailableMemory available_memory() {
  AvailableMemory least;
  const std::size_t meminfo = meminfo_available_bytes(read_text("/proc/meminfo"));
  if (meminfo > 0) consider(least, meminfo, "MemAvailable");
  consider_cgroups(least);
  const std::string status = read_text("/proc/self/status");
  consider_rlimit(least, RLIMIT_AS, status, "VmSize", "RLIMIT_AS");
  consider_rlimit(least, RLIMIT_DATA, status, "VmData", "RLIMIT_DATA");
  if (!least.known()) least.bytes = std::numeric_limits<std::size_t>::max();
  return least;
}

bool cap_data_growth(std::size_t bytes, std::string source) {
  rlimit limit{};
  if (getrlimit(RLIMIT_DATA, &limit) != 0) return false;
  const std::size_t used = status_field_bytes(read_text("/proc/self/status"), "VmData");
  const std::size_t cap = used + std::min(bytes, std::numeric_limits<std::size_t>::max() - used);
  if (limit.rlim_cur != RLIM_INFINITY && static_cast<std::size_t>(limit.rlim_cur) <= cap) return true;
  limit.rlim_cur = static_cast<rlim_t>(cap);
  if (setrlimit(RLIMIT_DATA, &limit) != 0) return false;
  OwnLimit& own = own_limit();
  const std::lock_guard lock(own.mutex);
  own.resource = RLIMIT_DATA;
  own.value = limit.rlim_cur;
  own.source = std::move(source);
  return true;
}

}  // namespace clothsim
