// How much memory this process can still take: the least of what the system, its control group
// and its resource limits leave.
//
//   MemAvailable   /proc/meminfo: what the kernel estimates can be allocated without swapping,
//                  counting page cache it can drop (the figure `free` shows as "available");
//   cgroup limit   the memory controller's limit minus its current usage, for this process's
//                  group and each group above it (v2: memory.max and memory.current; v1:
//                  memory.limit_in_bytes and memory.usage_in_bytes), where there is a limit;
//   RLIMIT_AS      the address-space limit minus the address space already mapped (VmSize);
//   RLIMIT_DATA    the data-segment limit minus the data already mapped (VmData).
// A data-segment limit this process set itself (cap_data_growth) restates the limit it was taken
// from, and carries that limit's name: a later check names what the user set ("RLIMIT_AS",
// "--max-memory"), not the cap derived from it, which can be the least by a few pages.
// Each source that cannot be read is left out; with none readable, the memory is unknown and
// `bytes` is the largest size_t. The figures are a snapshot: other processes may take or free
// memory after it.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace clothsim {

struct AvailableMemory {
  std::size_t bytes = 0;
  std::string source;  // what limits it: "MemAvailable", "the cgroup limit", "RLIMIT_AS", ...
  bool known() const { return !source.empty(); }
};

AvailableMemory available_memory();

// Caps the data this process may still map (RLIMIT_DATA's soft limit) at what it has mapped now
// plus `bytes`, unless the limit is that low already: past it an allocation fails (std::bad_alloc)
// instead of the process growing until the kernel's out-of-memory killer ends it. Children
// started after it (ffmpeg) inherit the cap. `source` names where `bytes` came from (an
// AvailableMemory's source, or "--max-memory"); available_memory() then reports the cap under that
// name. Returns false if the limit could not be set.
bool cap_data_growth(std::size_t bytes, std::string source = "RLIMIT_DATA");

// The pieces, for tests: the MemAvailable line of /proc/meminfo text in bytes (0 if absent), and
// a cgroup value ("max" or a number) in bytes (0 if it is "max" or not a number).
std::size_t meminfo_available_bytes(std::string_view meminfo);
std::size_t cgroup_value_bytes(std::string_view text);

}  // namespace clothsim
