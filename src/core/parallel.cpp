#include "core/parallel.h"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace clothsim {

int hardware_thread_count() { return std::max(1, omp_get_num_procs()); }

int idle_hardware_threads() {
  const int hardware = hardware_thread_count();
  double load = 0.0;
  if (getloadavg(&load, 1) != 1 || !(load >= 0.0)) return hardware;
  const int busy = static_cast<int>(std::lround(load));
  return std::clamp(hardware - busy, 1, hardware);
}

int resolve_thread_count(int requested, std::size_t problem_size, std::size_t parallel_threshold, int available) {
  if (requested > 0) return requested;
  if (problem_size < parallel_threshold) return 1;
  return available > 0 ? available : idle_hardware_threads();
}

}  // namespace clothsim
