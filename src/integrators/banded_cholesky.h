// The Cholesky factor L L^T of a symmetric positive definite banded matrix, for the exact solves
// of implicit Euler's coarse grids: the two-level preconditioner's 4 x 4 aggregates and the
// multigrid's coarsest level (integrators/implicit_euler.h, integrators/multigrid.h).
//
// Storage: dofs rows of bandwidth + 1 doubles. The matrix is given by its lower triangle, entry
// (i, j) with i - bandwidth <= j <= i, and factored in place; the factor is then kept twice, in the
// layouts that let both substitutions read memory in ascending order (L by rows in column order,
// and L^T by rows). Cost: dofs x bandwidth^2 to factor, 4 dofs x bandwidth per solve, serial.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

namespace clothsim {

class BandedCholesky {
 public:
  void resize(std::size_t dofs, std::size_t bandwidth);
  std::size_t dofs() const { return dofs_; }
  std::size_t bandwidth() const { return bandwidth_; }
  // Zeroes the matrix before its entries are added.
  void clear();
  // Entry (i, j) of the lower triangle, j <= i <= j + bandwidth(), before factor().
  double& lower(std::size_t i, std::size_t j) { return band_[i * (bandwidth_ + 1) + (i - j)]; }
  // Factors the matrix in place. An unknown no equation touches (zero diagonal) gets a 1 there,
  // which keeps the factor definite; its right-hand side is zero, and so is its solution.
  void factor();
  // Solves A x = b in place: `x` holds b on entry (dofs() values).
  void solve(std::span<double> x) const;
  std::size_t bytes() const { return (band_.capacity() + upper_.capacity()) * sizeof(double); }
  static std::size_t bytes_for(std::size_t dofs, std::size_t bandwidth) {
    return 2 * dofs * (bandwidth + 1) * sizeof(double);
  }

 private:
  std::size_t dofs_ = 0;
  std::size_t bandwidth_ = 0;
  std::vector<double> band_;   // [dofs_ (bandwidth_ + 1)]: the lower triangle, then L by rows in column order
  std::vector<double> upper_;  // [dofs_ (bandwidth_ + 1)]: L^T by rows, for the backward substitution
};

}  // namespace clothsim
