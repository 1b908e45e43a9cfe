// The multigrid V-cycle (integrators/multigrid.h) on a synthetic symmetric positive definite
// matrix with the lattice's pattern, with either fine smoother (lines and points): it is a
// symmetric positive definite operator (what conjugate gradients needs), zero where nothing is
// solved for and in the held directions, and the same bits for any thread count; solving lines
// makes it contract the error of a system stiff along the lattice's lines much faster.
#include "integrators/multigrid.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <vector>

namespace clothsim {
namespace {

// M + sum over coupled pairs (p, q) of (e_p - e_q)(e_p - e_q)^T (x) K_pq, K_pq = k n n^T + s I
// with a random direction n: stiff along n like a connector, weak across it. Pairs: the lattice
// matrix's offsets (0, +-1), (+-1, 0), (+-1, +-1), (0, +-2), (+-2, 0). `sheet`: the stiff pairs'
// n along their lattice direction (x for (0, 1), y for (1, 0)) within a few degrees, as a flat
// sheet's connectors lie, instead of anywhere.
struct LatticeSystem {
  std::size_t rows = 0;
  std::size_t cols = 0;
  std::vector<std::uint32_t> row_offset;
  std::vector<std::uint32_t> column;
  std::vector<Mat3> block;
  std::vector<Mat3> diagonal_inverse;
  std::vector<std::uint8_t> free;
  std::vector<Hold> hold;
  std::vector<Vec3> normal;
  bool holding = false;

  MultigridFineSystem view() const {
    return {row_offset, column, block, diagonal_inverse, free, hold, normal, holding};
  }
};

LatticeSystem make_system(std::size_t rows, std::size_t cols, unsigned seed, bool sheet = false) {
  LatticeSystem system;
  system.rows = rows;
  system.cols = cols;
  const std::size_t n = rows * cols;
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  const auto coupling = [&](int k) {
    const bool stiff = k == 6 || k == 9;
    Vec3 direction{uniform(random), uniform(random), uniform(random)};
    if (sheet && stiff) direction = (k == 6 ? Vec3{1.0, 0.0, 0.0} : Vec3{0.0, 1.0, 0.0}) + 0.05 * direction;
    direction = (1.0 / norm(direction)) * direction;
    return (stiff ? 1e4 : 10.0) * outer(direction, direction) + Mat3::diagonal(stiff ? 1.0 : 0.1);
  };
  const int offsets[12][2] = {{-2, 0}, {-1, -1}, {-1, 0}, {-1, 1}, {0, -2}, {0, -1},
                              {0, 1},  {0, 2},   {1, -1}, {1, 0},  {1, 1},  {2, 0}};
  // Couplings by (p, offset index), symmetric: K for (q, -offset) is K for (p, offset).
  std::vector<Mat3> pair(n * 12);
  for (std::size_t p = 0; p < n; ++p) {
    for (int k = 6; k < 12; ++k) pair[p * 12 + static_cast<std::size_t>(k)] = coupling(k);
  }
  system.row_offset.push_back(0);
  std::vector<Mat3> diagonal(n, Mat3::diagonal(1e-2));
  for (std::size_t p = 0; p < n; ++p) {
    const auto i = static_cast<int>(p / cols);
    const auto j = static_cast<int>(p % cols);
    struct Entry {
      std::uint32_t q;
      Mat3 value;
    };
    std::vector<Entry> entries;
    for (int k = 0; k < 12; ++k) {
      const int qi = i + offsets[k][0];
      const int qj = j + offsets[k][1];
      if (qi < 0 || qj < 0 || qi >= static_cast<int>(rows) || qj >= static_cast<int>(cols)) continue;
      const std::size_t q = static_cast<std::size_t>(qi) * cols + static_cast<std::size_t>(qj);
      const Mat3& value =
          k >= 6 ? pair[p * 12 + static_cast<std::size_t>(k)] : pair[q * 12 + static_cast<std::size_t>(11 - k)];
      entries.push_back({static_cast<std::uint32_t>(q), -value});
      diagonal[p] += value;
    }
    entries.push_back({static_cast<std::uint32_t>(p), Mat3{}});
    std::sort(entries.begin(), entries.end(), [](const Entry& a, const Entry& b) { return a.q < b.q; });
    for (const Entry& entry : entries) {
      system.column.push_back(entry.q);
      system.block.push_back(entry.q == p ? diagonal[p] : entry.value);
    }
    system.row_offset.push_back(static_cast<std::uint32_t>(system.column.size()));
  }
  system.free.assign(n, 1);
  system.free[0] = system.free[cols - 1] = 0;  // two anchored corners
  system.hold.assign(n, Hold::none);
  system.normal.assign(n, Vec3{});
  system.diagonal_inverse.resize(n);
  for (std::size_t p = 0; p < n; ++p) system.diagonal_inverse[p] = system.free[p] ? inverse(diagonal[p]) : Mat3{};
  return system;
}

// Holds a few particles along a normal and one in all directions, with implicit Euler's
// smoother blocks for them (the inverse of S D S completed by n n^T).
void hold_some(LatticeSystem& system, const std::vector<Mat3>& diagonal) {
  system.holding = true;
  const Vec3 normal = (1.0 / std::sqrt(3.0)) * Vec3{1.0, 1.0, -1.0};
  for (std::size_t p = 5; p < system.free.size(); p += 7) {
    system.hold[p] = Hold::normal;
    system.normal[p] = normal;
    const Mat3& d = diagonal[p];
    const Vec3 dn = d * normal;
    system.diagonal_inverse[p] =
        inverse(d - outer(normal, dn) - outer(dn, normal) + (dot(normal, dn) + 1.0) * outer(normal, normal));
  }
  system.hold[12] = Hold::all;
  system.normal[12] = normal;
  system.diagonal_inverse[12] = Mat3{};
}

std::vector<Vec3> random_vector(const LatticeSystem& system, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  std::vector<Vec3> v(system.free.size());
  for (std::size_t p = 0; p < v.size(); ++p) {
    const Vec3 value{uniform(random), uniform(random), uniform(random)};
    v[p] = system.free[p] ? held_vector(system.hold[p], system.normal[p], value) : Vec3{};
  }
  return v;
}

double dot_all(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  double sum = 0.0;
  for (std::size_t p = 0; p < a.size(); ++p) sum += dot(a[p], b[p]);
  return sum;
}

void expect_symmetric_positive_definite(LatticeSystem& system, bool lines) {
  LatticeMultigrid multigrid(system.rows, system.cols, lines);
  multigrid.setup(system.view(), 1);
  const std::size_t n = system.free.size();
  std::vector<Vec3> ba(n), bb(n);
  for (unsigned trial = 0; trial < 5; ++trial) {
    const std::vector<Vec3> a = random_vector(system, 2 * trial + 1);
    const std::vector<Vec3> b = random_vector(system, 2 * trial + 2);
    multigrid.apply(a, ba, 1);
    multigrid.apply(b, bb, 1);
    const double scale = std::sqrt(dot_all(a, ba) * dot_all(b, bb));
    EXPECT_GT(dot_all(a, ba), 0.0);
    EXPECT_NEAR(dot_all(b, ba), dot_all(a, bb), 1e-12 * scale) << "trial " << trial << ", lines " << lines;
    for (std::size_t p = 0; p < n; ++p) {
      if (!system.free[p] || system.hold[p] == Hold::all) {
        EXPECT_EQ(ba[p], Vec3{}) << p;
      } else if (system.hold[p] == Hold::normal) {
        EXPECT_NEAR(dot(ba[p], system.normal[p]), 0.0, 1e-12 * norm(ba[p])) << p;
      }
    }
  }
}

TEST(LatticeMultigrid, VCycleIsSymmetricPositiveDefinite) {
  // Sides giving 1 to 3 coarse levels, even and odd, and lattices 4 or fewer nodes wide.
  for (const auto& [rows, cols] :
       {std::pair<std::size_t, std::size_t>{5, 6}, {17, 16}, {40, 33}, {2, 2}, {3, 30}, {6, 4}}) {
    LatticeSystem system = make_system(rows, cols, 7);
    for (bool lines : {true, false}) {
      SCOPED_TRACE(testing::Message() << rows << " x " << cols);
      expect_symmetric_positive_definite(system, lines);
    }
  }
}

TEST(LatticeMultigrid, VCycleIsSymmetricPositiveDefiniteWithHeldParticles) {
  LatticeSystem system = make_system(24, 21, 3);
  std::vector<Mat3> diagonal(system.free.size());
  for (std::size_t p = 0; p < diagonal.size(); ++p) {
    for (std::uint32_t k = system.row_offset[p]; k < system.row_offset[p + 1]; ++k) {
      if (system.column[k] == p) diagonal[p] = system.block[k];
    }
  }
  hold_some(system, diagonal);
  for (bool lines : {true, false}) expect_symmetric_positive_definite(system, lines);
}

// Levels 0 and 1 of a 70 x 80 lattice have 1024 nodes or more and run in parallel.
TEST(LatticeMultigrid, SameBitsForAnyThreadCount) {
  LatticeSystem system = make_system(70, 80, 11);
  const std::vector<Vec3> residual = random_vector(system, 5);
  const auto apply = [&](int threads, bool lines) {
    LatticeMultigrid multigrid(system.rows, system.cols, lines);
    multigrid.setup(system.view(), threads);
    std::vector<Vec3> result(residual.size());
    multigrid.apply(residual, result, threads);
    return result;
  };
  for (bool lines : {true, false}) {
    const std::vector<Vec3> one = apply(1, lines);
    for (int threads : {2, 3}) {
      const std::vector<Vec3> many = apply(threads, lines);
      EXPECT_EQ(std::memcmp(one.data(), many.data(), one.size() * sizeof(Vec3)), 0)
          << threads << " threads, lines " << lines;
    }
  }
}

// A x, from the CSR.
std::vector<Vec3> product(const LatticeSystem& system, const std::vector<Vec3>& x) {
  std::vector<Vec3> result(x.size());
  for (std::size_t p = 0; p < x.size(); ++p) {
    if (!system.free[p]) continue;
    for (std::uint32_t k = system.row_offset[p]; k < system.row_offset[p + 1]; ++k) {
      if (system.free[system.column[k]]) result[p] += system.block[k] * x[system.column[k]];
    }
  }
  return result;
}

// The V-cycle V as a stationary iteration, e <- e - V A e: its error's energy norm after 8 cycles
// from a random error, per cycle (an estimate of the contraction factor).
double contraction(const LatticeSystem& system, bool lines) {
  LatticeMultigrid multigrid(system.rows, system.cols, lines);
  multigrid.setup(system.view(), 1);
  std::vector<Vec3> error = random_vector(system, 9);
  std::vector<Vec3> correction(error.size());
  const auto energy = [&] { return std::sqrt(dot_all(error, product(system, error))); };
  const double start = energy();
  constexpr int kCycles = 8;
  for (int cycle = 0; cycle < kCycles; ++cycle) {
    multigrid.apply(product(system, error), correction, 1);
    for (std::size_t p = 0; p < error.size(); ++p) error[p] -= correction[p];
  }
  return std::pow(energy() / start, 1.0 / kCycles);
}

// A sheet's system: each particle's x coupled to its row neighbours', its y to its column
// neighbours', 1000 times more strongly than anything else.
TEST(LatticeMultigrid, SolvingLinesContractsAnisotropicErrorsFaster) {
  const LatticeSystem system = make_system(64, 48, 5, true);
  const double lines = contraction(system, true);
  const double points = contraction(system, false);
  // Measured: 0.39 and 0.58 per cycle (with n anywhere, 0.63 and 0.65): 7 cycles to 1e-3 against 13.
  EXPECT_LT(lines, 0.75 * points) << "lines " << lines << ", points " << points;
  EXPECT_LT(lines, 0.45);
}

TEST(LatticeMultigrid, ReportsItsBytes) {
  for (bool lines : {true, false}) {
    LatticeMultigrid multigrid(128, 128, lines);
    EXPECT_EQ(multigrid.level_count(), 5u);  // 128, 64, 32, 16, 8
    EXPECT_EQ(multigrid.bytes(), LatticeMultigrid::bytes_for(128, 128, lines)) << "lines " << lines;
  }
}

}  // namespace
}  // namespace clothsim
