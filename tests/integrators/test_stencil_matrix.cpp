// The multigrid's stored operator (integrators/stencil_matrix.h): the upper half of a lattice
// stencil in single precision, whose row products must be those of the whole symmetric matrix,
// at every border and on lattices too narrow for some offsets. The oracle is the dense product
// over every pair of nodes.
#include "integrators/stencil_matrix.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>
#include <vector>

namespace clothsim {
namespace {

using Offset = SymmetricStencilMatrix::Offset;

constexpr std::array<Offset, 7> kFine = {{{0, 0}, {0, 1}, {0, 2}, {1, -1}, {1, 0}, {1, 1}, {2, 0}}};
constexpr std::array<Offset, 11> kCoarse = {
    {{0, 0}, {0, 1}, {0, 2}, {1, -2}, {1, -1}, {1, 0}, {1, 1}, {1, 2}, {2, -1}, {2, 0}, {2, 1}}};

Mat3 rounded(const Mat3& m) {
  const auto r = [](double value) { return static_cast<double>(static_cast<float>(value)); };
  return {
      {r(m(0, 0)), r(m(0, 1)), r(m(0, 2))}, {r(m(1, 0)), r(m(1, 1)), r(m(1, 2))}, {r(m(2, 0)), r(m(2, 1)), r(m(2, 2))}};
}

Mat3 transposed(const Mat3& m) {
  return {{m(0, 0), m(1, 0), m(2, 0)}, {m(0, 1), m(1, 1), m(2, 1)}, {m(0, 2), m(1, 2), m(2, 2)}};
}

// Fills every slot of every row with a random block (also where the neighbour lies outside the
// lattice: the products must ignore those) and checks each row's product against the dense one.
void expect_dense_products(std::size_t rows, std::size_t cols, std::span<const Offset> upper, unsigned seed) {
  SymmetricStencilMatrix matrix(rows, cols, upper);
  const std::size_t n = rows * cols;
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  const auto random_vec = [&] { return Vec3{uniform(random), uniform(random), uniform(random)}; };
  // dense[p][q]: the block of row p to node q, from the blocks as stored (rounded).
  std::vector<std::vector<Mat3>> dense(n, std::vector<Mat3>(n));
  for (std::size_t p = 0; p < n; ++p) {
    for (std::size_t s = 0; s < upper.size(); ++s) {
      Mat3 block{random_vec(), random_vec(), random_vec()};
      if (s == 0) block = block + transposed(block);  // a diagonal block is symmetric
      matrix.set(p, s, block);
      const auto i = static_cast<long>(p / cols) + upper[s][0];
      const auto j = static_cast<long>(p % cols) + upper[s][1];
      if (i < 0 || j < 0 || i >= static_cast<long>(rows) || j >= static_cast<long>(cols)) continue;
      const std::size_t q = static_cast<std::size_t>(i) * cols + static_cast<std::size_t>(j);
      dense[p][q] = rounded(block);
      dense[q][p] = transposed(rounded(block));
    }
  }
  std::vector<Vec3> x(n);
  for (Vec3& value : x) value = random_vec();
  for (std::size_t p = 0; p < n; ++p) {
    Vec3 expected;
    double scale = 0.0;
    for (std::size_t q = 0; q < n; ++q) {
      expected += dense[p][q] * x[q];
      scale += norm(dense[p][q].row0) + norm(dense[p][q].row1) + norm(dense[p][q].row2);
    }
    const Vec3 product = matrix.row_product(p, x);
    EXPECT_LE(norm(product - expected), 1e-13 * scale) << rows << " x " << cols << ", node " << p;
  }
}

TEST(SymmetricStencilMatrix, RowProductsAreTheWholeSymmetricMatrixs) {
  for (const auto& [rows, cols] :
       {std::pair<std::size_t, std::size_t>{1, 1}, {1, 7}, {7, 1}, {2, 2}, {3, 5}, {5, 3}, {6, 7}, {9, 9}}) {
    expect_dense_products(rows, cols, kFine, 3);
    expect_dense_products(rows, cols, kCoarse, 4);
  }
}

TEST(SymmetricStencilMatrix, KeepsBlocksInSinglePrecision) {
  SymmetricStencilMatrix matrix(5, 5, kFine);
  const double value = 1.0 + 1e-10;  // not a float
  matrix.set(12, 0, Mat3::diagonal(value));
  std::vector<Vec3> x(25);
  x[12] = {1.0, 0.0, 0.0};
  EXPECT_EQ(matrix.row_product(12, x).x, 1.0);
  matrix.clear_row(12);
  EXPECT_EQ(matrix.row_product(12, x), Vec3{});
}

TEST(SymmetricStencilMatrix, FindsItsSlots) {
  SymmetricStencilMatrix matrix(8, 8, kFine);
  EXPECT_EQ(matrix.slot_count(), 7u);
  EXPECT_EQ(matrix.slot(0, 0), 0u);
  EXPECT_EQ(matrix.slot(2, 0), 6u);
  EXPECT_EQ(matrix.slot(1, 2), SymmetricStencilMatrix::kMaxSlots);  // a coarse offset, not a fine one
  EXPECT_EQ(matrix.bytes(), SymmetricStencilMatrix::bytes_for(64, 7));
}

}  // namespace
}  // namespace clothsim
