#include "core/parallel.h"

#include <omp.h>

#include <algorithm>

namespace clothsim {

int hardware_thread_count() { return std::max(1, omp_get_num_procs()); }

int resolve_thread_count(int requested, std::size_t problem_size, std::size_t parallel_threshold) {
  if (requested > 0) return requested;
  return problem_size >= parallel_threshold ? hardware_thread_count() : 1;
}

}  // namespace clothsim
