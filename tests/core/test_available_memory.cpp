// What the system leaves this process (core/available_memory.h): /proc/meminfo and cgroup values
// parsed, the least of the sources found with its name, an address-space limit seen, a cap this
// process set named by the limit it came from, and the cap on growth turning an allocation past it into std::bad_alloc (in child processes, so the test's
// own limits stay as they are). Under AddressSanitizer, whose operator new ends the process
// instead of throwing, the cap is seen to hold by that end.
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <cstdint>
#include <new>
#include <vector>

#include "core/available_memory.h"
#include "test_checks.h"

namespace clothsim {
namespace {

constexpr std::uint64_t kKiB = 1024;
constexpr std::uint64_t kMiB = kKiB * kKiB;
constexpr std::uint64_t kGiB = kMiB * kKiB;

TEST(AvailableMemory, ReadsMeminfoAndCgroupValues) {
  EXPECT_EQ(meminfo_available_bytes("MemTotal:       24683652 kB\nMemFree:        21681044 kB\n"
                                    "MemAvailable:   23272896 kB\nBuffers:  1 kB\n"),
            std::size_t{23272896} * 1024);
  EXPECT_EQ(meminfo_available_bytes("MemTotal: 5 kB\n"), 0u);
  EXPECT_EQ(cgroup_value_bytes("max\n"), 0u);
  EXPECT_EQ(cgroup_value_bytes("1073741824\n"), std::size_t{1} << 30);
  EXPECT_EQ(cgroup_value_bytes("junk"), 0u);
}

TEST(AvailableMemory, NamesTheLeastSourceAndSeesAnAddressSpaceLimit) {
  const AvailableMemory available = available_memory();
  ASSERT_TRUE(available.known()) << "no /proc/meminfo on this Linux machine?";
  EXPECT_GT(available.bytes, 0u);
  // In a child whose address-space limit leaves it 1 GiB more than it has mapped, that limit
  // (less what is mapped) is the least.
  const rlim_t cap = checks::mapped_address_space() + kGiB;
  ASSERT_GT(cap, kGiB) << "no VmSize in /proc/self/status";
  const pid_t pid = ::fork();
  if (pid == 0) {
    rlimit limit{cap, cap};
    if (::setrlimit(RLIMIT_AS, &limit) != 0) ::_exit(2);
    const AvailableMemory limited = available_memory();
    ::_exit(limited.source == "RLIMIT_AS" && limited.bytes <= kGiB && limited.bytes > kGiB / 2 ? 0 : 1);
  }
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "status " << status;
}

// The cap the command sets from the least limit restates that limit: a later check, which finds
// the cap the least (here by 16 MiB, as allocations between the two can make it), names the limit
// it came from. A data-segment limit set by anyone else keeps its own name.
TEST(AvailableMemory, ADataCapThisProcessSetCarriesTheNameOfItsLimit) {
  const rlim_t cap = checks::mapped_address_space() + kGiB;
  const pid_t pid = ::fork();
  if (pid == 0) {
    rlimit limit{cap, cap};
    if (::setrlimit(RLIMIT_AS, &limit) != 0) ::_exit(2);
    const AvailableMemory before = available_memory();
    if (before.source != "RLIMIT_AS") ::_exit(3);
    if (!cap_data_growth(before.bytes - 16 * kMiB, before.source)) ::_exit(4);
    const AvailableMemory after = available_memory();
    if (after.source != "RLIMIT_AS" || after.bytes > before.bytes - 16 * kMiB) ::_exit(5);
    rlimit data{};
    if (::getrlimit(RLIMIT_DATA, &data) != 0) ::_exit(6);
    data.rlim_cur -= 32 * kMiB;  // lower still, and not by cap_data_growth
    if (::setrlimit(RLIMIT_DATA, &data) != 0) ::_exit(7);
    ::_exit(available_memory().source == "RLIMIT_DATA" ? 0 : 8);
  }
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "status " << status;
}

TEST(AvailableMemory, CappedGrowthFailsWithBadAllocInsteadOfGrowing) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    if (!cap_data_growth(256 * kMiB)) ::_exit(2);
    try {
      std::vector<char> fits(64 * kMiB, 1);
      std::vector<char> too_much(512 * kMiB, 1);
      ::_exit(3);  // the cap did not hold
    } catch (const std::bad_alloc&) {
      ::_exit(0);
    }
  }
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
#if defined(__SANITIZE_ADDRESS__)
  // AddressSanitizer's operator new never throws: an allocation it cannot map ends the process
  // with its "allocator is out of memory" report and exit code 1. The cap held all the same.
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 1) << "status " << status;
#else
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "status " << status;
#endif
}

}  // namespace
}  // namespace clothsim
