#include "integrators/banded_cholesky.h"

#include <algorithm>
#include <cmath>

namespace clothsim {
namespace {

// sum_k a[k] b[k] over k in [0, count), in four interleaved partial sums added in a fixed order:
// the same bits every time, without the latency of one long chain of dependent additions.
double band_dot(const double* a, const double* b, std::size_t count) {
  double s0 = 0.0, s1 = 0.0, s2 = 0.0, s3 = 0.0;
  std::size_t k = 0;
  for (; k + 4 <= count; k += 4) {
    s0 += a[k] * b[k];
    s1 += a[k + 1] * b[k + 1];
    s2 += a[k + 2] * b[k + 2];
    s3 += a[k + 3] * b[k + 3];
  }
  for (; k < count; ++k) s0 += a[k] * b[k];
  return (s0 + s1) + (s2 + s3);
}

}  // namespace

void BandedCholesky::resize(std::size_t dofs, std::size_t bandwidth) {
  dofs_ = dofs;
  bandwidth_ = bandwidth;
  band_.assign(dofs * (bandwidth + 1), 0.0);
  upper_.assign(band_.size(), 0.0);
}

void BandedCholesky::clear() { std::fill(band_.begin(), band_.end(), 0.0); }

void BandedCholesky::factor() {
  const std::size_t width = bandwidth_ + 1;
  const std::size_t bandwidth = bandwidth_;
  for (std::size_t i = 0; i < dofs_; ++i) {
    if (band_[i * width] == 0.0) band_[i * width] = 1.0;
  }
  // L L^T in place: entry (i, j), i - bandwidth <= j <= i, at band[i width + i - j].
  for (std::size_t j = 0; j < dofs_; ++j) {
    double* row_j = &band_[j * width];
    const std::size_t first_j = j > bandwidth ? j - bandwidth : 0;
    double diagonal = row_j[0];
    for (std::size_t k = first_j; k < j; ++k) diagonal -= row_j[j - k] * row_j[j - k];
    diagonal = diagonal > 0.0 ? std::sqrt(diagonal) : 1.0;  // SPD in exact arithmetic
    row_j[0] = diagonal;
    const std::size_t last = std::min(dofs_ - 1, j + bandwidth);
    for (std::size_t i = j + 1; i <= last; ++i) {
      double* row_i = &band_[i * width];
      const std::size_t first = i > bandwidth ? i - bandwidth : 0;  // >= first_j as i > j
      double sum = row_i[i - j];
      for (std::size_t k = first; k < j; ++k) sum -= row_i[i - k] * row_j[j - k];
      row_i[i - j] = sum / diagonal;
    }
  }
  // Layouts for the substitutions, each reading memory in ascending order: L^T by rows, entry
  // (i, k) at upper[i width + k - i], copied out first; then, in place of the band, L by rows in
  // column order, entry (i, j) at band[i width + bandwidth - (i - j)] for j < i and the diagonal at
  // band[i width + bandwidth]. (A third copy, for the band itself, would be a third of the
  // integrator's memory on a large sheet: docs/performance.md, "Memory".)
  for (std::size_t i = 0; i < dofs_; ++i) {
    const std::size_t last = std::min(dofs_ - 1, i + bandwidth);
    for (std::size_t k = i; k <= last; ++k) upper_[i * width + (k - i)] = band_[k * width + (k - i)];
  }
  for (std::size_t i = 0; i < dofs_; ++i) {
    const std::size_t first = i > bandwidth ? i - bandwidth : 0;
    double* row = &band_[i * width];
    const double diagonal = row[0];
    // row[d] = L(i, i - d), d = 1 .. i - first, becomes row[m] = L(i, first + m), m = 0 .. i - first - 1.
    std::reverse(row + 1, row + 1 + (i - first));
    std::copy(row + 1, row + 1 + (i - first), row);
    row[bandwidth] = diagonal;
  }
}

void BandedCholesky::solve(std::span<double> x) const {
  const std::size_t width = bandwidth_ + 1;
  const std::size_t bandwidth = bandwidth_;
  for (std::size_t i = 0; i < dofs_; ++i) {  // L y = b, with L by rows in column order (see factor)
    const double* row_i = &band_[i * width];
    const std::size_t first = i > bandwidth ? i - bandwidth : 0;
    // row_i[m] = L(i, first + m) for m < i - first; row_i[bandwidth] = L(i, i).
    x[i] = (x[i] - band_dot(row_i, &x[first], i - first)) / row_i[bandwidth];
  }
  for (std::size_t i = dofs_; i-- > 0;) {  // L^T x = y
    const double* row_i = &upper_[i * width];
    const std::size_t last = std::min(dofs_ - 1, i + bandwidth);
    x[i] = (x[i] - band_dot(row_i + 1, &x[i + 1], last - i)) / row_i[0];
  }
}

}  // namespace clothsim
