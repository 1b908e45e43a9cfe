// A STREAM-like memory bandwidth probe (after J. McCalpin's STREAM "triad", a[i] = b[i] + s c[i]),
// for the roofline estimate in docs/performance.md. Reports the best of several repetitions for
// array sizes that fit in the caches and ones that do not, on 1 and on all threads.
//
//   build/bench/bench/clothsim_stream
//
// Bytes counted per element: 3 x 8 (two reads, one write), as STREAM counts them; the write's
// read-for-ownership traffic is not counted, so the figure is what a kernel that streams the same
// way can expect.
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <vector>

int main() {
  const int all_threads = omp_get_num_procs();
  std::printf("%10s %8s %12s %12s\n", "array", "threads", "triad GB/s", "GFlop/s");
  for (std::size_t bytes_per_array : {std::size_t{256} << 10, std::size_t{2} << 20, std::size_t{8} << 20,
                                      std::size_t{64} << 20, std::size_t{256} << 20}) {
    const std::size_t n = bytes_per_array / sizeof(double);
    std::vector<double> a(n, 0.0), b(n, 1.0), c(n, 2.0);
    const double scalar = 3.0;
    for (int threads : {1, all_threads}) {
      const int repetitions =
          static_cast<int>(std::clamp<std::size_t>((std::size_t{1} << 31) / (3 * bytes_per_array), 5, 2000));
      double best = 1e30;
      for (int r = 0; r < repetitions; ++r) {
        const auto start = std::chrono::steady_clock::now();
        const auto count = static_cast<long long>(n);
#pragma omp parallel for schedule(static) num_threads(threads)
        for (long long i = 0; i < count; ++i)
          a[static_cast<std::size_t>(i)] = b[static_cast<std::size_t>(i)] + scalar * c[static_cast<std::size_t>(i)];
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        best = std::min(best, seconds);
      }
      const double gbs = 3.0 * static_cast<double>(bytes_per_array) / best / 1e9;
      const double gflops = 2.0 * static_cast<double>(n) / best / 1e9;
      std::printf("%7zu KiB %8d %12.1f %12.2f\n", bytes_per_array >> 10, threads, gbs, gflops);
    }
    if (a[n / 2] != 7.0) std::printf("unexpected result\n");
  }
  return 0;
}
