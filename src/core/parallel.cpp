#include "core/parallel.h"

#include <omp.h>
#include <sched.h>

#include <algorithm>
#include <charconv>
#include <chrono>
#include <fstream>
#include <iterator>
#include <string>
#include <thread>

namespace clothsim {

int hardware_thread_count() {
  cpu_set_t mask;
  CPU_ZERO(&mask);
  if (sched_getaffinity(0, sizeof(mask), &mask) == 0) return std::max(1, CPU_COUNT(&mask));
  return std::max(1, omp_get_num_procs());
}

int parse_procs_running(std::string_view proc_stat) {
  constexpr std::string_view kKey = "\nprocs_running ";
  const std::size_t at = proc_stat.find(kKey);
  if (at == std::string_view::npos) return -1;
  const char* begin = proc_stat.data() + at + kKey.size();
  int value = -1;
  const auto [end, error] = std::from_chars(begin, proc_stat.data() + proc_stat.size(), value);
  return error == std::errc{} && end != begin ? value : -1;
}

int idle_threads(int available, int other_runnable) {
  return std::clamp(available - std::max(0, other_runnable), 1, std::max(1, available));
}

namespace {

// procs_running now, or -1 where /proc/stat cannot be read.
int sample_procs_running() {
  std::ifstream file("/proc/stat");
  if (!file) return -1;
  const std::string text(std::istreambuf_iterator<char>(file), {});
  return parse_procs_running(text);
}

}  // namespace

int idle_hardware_threads() {
  const int available = hardware_thread_count();
  constexpr int kSamples = 5;
  int least = -1;
  for (int sample = 0; sample < kSamples; ++sample) {
    if (sample > 0) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    const int running = sample_procs_running();
    if (running < 0) return available;
    least = least < 0 ? running : std::min(least, running);
  }
  return idle_threads(available, least - 1);  // the caller's own thread is running
}

int resolve_thread_count(int requested, std::size_t problem_size, std::size_t parallel_threshold, int available) {
  if (requested > 0) return requested;
  if (problem_size < parallel_threshold) return 1;
  return available > 0 ? available : idle_hardware_threads();
}

}  // namespace clothsim
