// The multigrid preconditioner of implicit Euler's conjugate gradients on a lattice: one
// symmetric V-cycle per application, geometric coarsening with Galerkin coarse matrices.
//
// Why. The system A = M + h C + h^2 K of stiff cloth at a frame-sized step is dominated by the
// connectors' stretch stiffness: a lattice Laplacian, strong along each connector and weak across
// it (cotton's shear and bending are 2 to 6 orders of magnitude softer than its stretch), whose
// condition number grows with the square of the lattice size. Block Jacobi took 420 to 900 CG
// iterations per step on cotton, the two-level additive preconditioner (Jacobi plus an exact
// solve on 4 x 4 piecewise-constant aggregates) about 89 at 128 x 128; this V-cycle takes 14 at
// 64 x 64 and at 128 x 128 with a point smoother, at most 19 in a step, and 6.2, at most 9, with
// the line smoother below (docs/performance.md, "The preconditioner", "Line smoothing").
//
// Levels. Level 0 is the lattice and implicit Euler's own block-sparse matrix (CSR of 3x3 blocks,
// not copied). Level l + 1 keeps every other node of level l in each direction: a rows x cols
// level has ceil(rows / 2) x ceil(cols / 2) nodes, node (I, J) sitting on node (2I, 2J) below.
// Coarsening stops at kCoarsestNodes nodes or fewer (8 x 8 from 128 x 128: four coarse levels),
// whose system is solved exactly by a banded Cholesky factor (integrators/banded_cholesky.h).
//
// Transfer. The prolongation P is bilinear interpolation, per lattice direction: a node on a
// coarse node takes its value, one between two coarse nodes their mean, and a last node past the
// last coarse node (an even side) the value of that node; its tensor product gives every fine
// node up to 4 coarse parents, each with a scalar weight times the 3x3 identity. Restriction is
// P^T. The coarse matrices are Galerkin's, A_{l+1} = P^T A_l P, assembled each step (A changes
// every step), so the coarse systems are exactly the energy of the interpolated functions. With
// the lattice's elements reaching 2 nodes (opposite radial springs), every level's matrix couples a
// node to its neighbours at offsets (di, dj) in [-2, 2]^2 except the 4 corners (+-2, +-2): 21 blocks,
// stored densely per node.
//
// Smoother. On the fine level, block line Gauss-Seidel (with `lines`, the default): each lattice
// row in turn solved exactly for its own unknowns, the other rows held, then each column (one
// sweep: all rows, then all columns). A connector's stretch stiffness couples a particle strongly
// to its two neighbours along that connector's line and hardly at all across it, so the errors a
// point smoother leaves are smooth along the lines and rough across them, which bilinear coarsening
// cannot represent; solving whole lines removes them. A line's matrix is block pentadiagonal (the
// opposite radial springs reach two nodes along it), factored as L D L^T once per setup. On
// 128 x 128 cotton CG then takes 6.2 iterations per step instead of 14.0, and the run 1.4 times
// less time (docs/performance.md, "Line smoothing"). The coarse levels,
// and the fine one without `lines`, use block point Gauss-Seidel (3x3 blocks
// and their inverses: the block Jacobi preconditioner's on level 0): 2 sweeps on level 0 and 1 on
// the coarse levels on each side of the coarse correction. Both read each level's matrix as
// integrators/stencil_matrix.h stores it (the upper half of the stencil in single precision: the
// sweeps were bound by memory). The nodes (or lines) are visited in bands of kBandRows = 4 whole
// rows (or lines): first the even bands, each in parallel with the others and in order within
// itself, then the odd ones. Elements reach 2 rows, so no two bands of the same parity share a
// matrix entry: each node is updated by one thread from values that do not depend on the thread
// count, and the bands are fixed by the lattice, not by the threads. On the way up the V the
// sweeps run in exactly the reverse order, the adjoint of the way down, so the V-cycle is a
// symmetric positive definite operator, as conjugate gradients require. (Gauss-Seidel converges
// on any symmetric positive definite matrix, with no damping to tune: damped Jacobi at 0.8
// diverged on cotton. A 9-colour Gauss-Seidel, (i mod 3, j mod 3), took as many iterations as the
// bands and 13 % more time: it reads the matrix in strides. Lines on the coarse levels as well
// took 5.0 iterations per step instead of 6.2, and more time.)
//
// Held particles (integrators/held_directions.h). The level-0 operator is S A S and the transfer
// S P: the Galerkin product filters each fine block, the prolongation filters what it adds, the
// smoother works in the free directions only. Anchored particles are outside the system: their
// rows and columns are left out of every product. setup() must run again when the held set changes.
//
// What was tried and rejected (smoothed aggregation, a multiplicative two-level cycle on
// aggregates) and why: docs/performance.md, "Implicit Euler's multigrid preconditioner".
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "core/mat3.h"
#include "integrators/banded_cholesky.h"
#include "integrators/held_directions.h"
#include "integrators/stencil_matrix.h"

namespace clothsim {

// The level-0 system: implicit Euler's matrix, its block Jacobi inverses and which particles and
// directions it solves for. The spans must stay valid until the next setup().
struct MultigridFineSystem {
  std::span<const std::uint32_t> row_offset;  // [particles + 1], rows of the CSR of 3x3 blocks
  std::span<const std::uint32_t> column;      // [blocks], ascending within a row
  std::span<const Mat3> block;                // [blocks], A
  std::span<const Mat3> diagonal_inverse;     // [particles], the smoother's blocks; unused where not free
  std::span<const std::uint8_t> free;         // [particles], 1 for the particles solved for
  std::span<const Hold> hold;                 // [particles], read only when holding
  std::span<const Vec3> normal;               // [particles], held normals, read only when holding
  bool holding = false;                       // some particle is held on a surface
};

class LatticeMultigrid {
 public:
  // Nodes per level at most for the exact solve that ends the V-cycle.
  static constexpr std::size_t kCoarsestNodes = 64;
  // Blocks per coarse row: offsets in [-2, 2]^2 but the corners (multigrid_stencil.inc's slots).
  static constexpr std::size_t kStencil = 21;
  // Gauss-Seidel sweeps on each side of the coarse correction, on the fine level and on the coarse
  // ones. Cotton at 128 x 128, 1 s (docs/performance.md), CG iterations per step (most in one):
  // 1 and 1 sweeps 18.5 (26); 2 and 1, 14.0 (19), the least time per step; 2 and 2, 12.0 (16);
  // 3 and 3, 9.6 (14).
  static constexpr int kFineSweeps = 2;
  static constexpr int kCoarseSweeps = 1;
  // Line sweeps (all rows, then all columns) on the fine level on each side, with `lines`. Cotton
  // as above: 1 sweep 6.2 iterations per step (9), the least time per step; 2 sweeps 4.5 (7).
  static constexpr int kFineLineSweeps = 1;

  // The hierarchy's structure for a rows x cols lattice (particle (i, j) at index i cols + j):
  // at least one coarse level. `lines`: the fine level's smoother solves lines (above), else points.
  LatticeMultigrid(std::size_t rows, std::size_t cols, bool lines);
  // The coarse matrices, their smoother blocks and the coarsest factor, from the fine system.
  void setup(const MultigridFineSystem& fine, int threads);
  // result = V-cycle applied to residual ([particles] each; residual zero where not solved for and
  // in the held directions). result is zero where not solved for.
  void apply(std::span<const Vec3> residual, std::span<Vec3> result, int threads);

  std::size_t level_count() const { return 1 + coarse_.size(); }
  std::size_t bytes() const;
  // bytes() of the hierarchy for a rows x cols lattice.
  static std::size_t bytes_for(std::size_t rows, std::size_t cols, bool lines);

 private:
  // Bilinear interpolation along one lattice direction, from a coarse level of `coarse_count`
  // nodes to the level below (multigrid_stencil.inc): a fine node's parents (1 or 2, ascending)
  // and a coarse node's children (the fine nodes 2I - 1 .. 2I + 1 that take part of its value,
  // ascending), each with its weight.
  struct Weights {
    std::size_t count = 0;
    std::array<std::size_t, 3> node{};
    std::array<double, 3> weight{};
  };
  struct Transfer {
    std::vector<Weights> parents;   // [fine nodes along the direction]
    std::vector<Weights> children;  // [coarse nodes along the direction]
  };
  static Transfer make_transfer(std::size_t fine_count, std::size_t coarse_count);

  struct CoarseLevel {
    std::size_t rows = 0;  // nodes
    std::size_t cols = 0;
    Transfer along_rows;  // from the level below, along its rows (row indices) and its columns
    Transfer along_cols;
    std::array<std::ptrdiff_t, kStencil> node_offset{};  // index of the node at each slot's offset, less I
    std::vector<Mat3> block;             // [nodes kStencil], row I's block to node I + offset(s) at I kStencil + s
    SymmetricStencilMatrix stencil;      // the same matrix, as the smoother and the residuals read it
    std::vector<Mat3> diagonal_inverse;  // [nodes], the smoother's blocks
    std::vector<Vec3> rhs;               // [nodes] restricted residual
    std::vector<Vec3> solution;          // [nodes]
    std::vector<Vec3> residual;          // [nodes] rhs - A solution, before restriction
  };

  // Level l's matrix row `node` (l = 0: the fine CSR) times `x`, in the solved directions.
  Vec3 row_product(std::size_t level, std::size_t node, std::span<const Vec3> x) const;
  // One Gauss-Seidel sweep over level l's colours, ascending (down the V) or descending.
  void smooth(std::size_t level, bool ascending, std::span<const Vec3> rhs, std::span<Vec3> x, int threads);
  // Gauss-Seidel on level l's nodes [first, end), ascending or descending: one band of smooth().
  void smooth_nodes(std::size_t level, std::size_t first, std::size_t end, bool ascending, std::span<const Vec3> rhs,
                    std::span<Vec3> x) const;
  // Gauss-Seidel's update of one node of level l.
  void update_node(std::size_t level, std::size_t node, std::span<const Vec3> rhs, std::span<Vec3> x) const;
  // residual = rhs - A x on level l's nodes [first, end) (zero where not solved for).
  void residual_nodes(std::size_t level, std::size_t first, std::size_t end, std::span<const Vec3> rhs,
                      std::span<const Vec3> x, std::span<Vec3> residual) const;
  // residual = rhs - A x on level l, then the next level's rhs = P^T residual.
  void restrict_residual(std::size_t level, std::span<const Vec3> rhs, std::span<const Vec3> x, int threads);
  // x += P (next level's solution) on level l.
  void prolong(std::size_t level, std::span<Vec3> x, int threads);
  // Level l + 1's matrix from level l's: P^T A_l P.
  void galerkin(std::size_t level, int threads);
  // Row `node` of level l + 1's matrix: one row of galerkin().
  void galerkin_row(std::size_t level, std::size_t node);
  // Adds weight w(q, J) times `block` to `row` (level l + 1's row (row, col), 21 slots) for each
  // parent J of level l's node (i, j).
  void add_to_parents(const CoarseLevel& next, std::size_t row, std::size_t col, std::size_t i, std::size_t j,
                      double weight, const Mat3& block, Mat3* sum) const;
  // The fine level's lines along `direction` (0: each row, 1: each column), factored.
  void factor_lines(int direction, int threads);
  // The fine level's sweeps on one side of the coarse correction: kFineLineSweeps of the lines
  // (rows, then columns; descending, columns, then rows) or kFineSweeps of the points.
  void smooth_fine(bool ascending, std::span<const Vec3> rhs, std::span<Vec3> x, int threads);
  // One line Gauss-Seidel sweep along `direction` over the fine level, ascending or descending.
  void smooth_lines(int direction, bool ascending, std::span<const Vec3> rhs, std::span<Vec3> x, int threads);
  // The lines [first, end) along `direction`, ascending or descending: one band of smooth_lines().
  void solve_lines(int direction, std::size_t first, std::size_t end, bool ascending, std::span<const Vec3> rhs,
                   std::span<Vec3> x);
  // One line's exact solve with the other lines held.
  void solve_line(int direction, std::size_t line, std::span<const Vec3> rhs, std::span<Vec3> x);
  // Fine row `node`'s blocks in the solved directions to itself and to the nodes 1 and 2 before it
  // on its line along `direction`, as fine_stencil_ holds them; a held normal direction gets the
  // diagonal's mean on the diagonal (its right-hand side is zero, and so its solution).
  std::array<Mat3, 3> line_blocks(std::size_t node, int direction) const;

  // One line's factor L D L^T, L unit lower block triangular: per node in line order (line l,
  // position t at index l length + t), its row of L (the blocks to the nodes 1 and 2 before it)
  // and the inverse of its block of D.
  struct LineFactor {
    std::vector<Mat3> below;             // [particles]
    std::vector<Mat3> two_below;         // [particles]
    std::vector<Mat3> diagonal_inverse;  // [particles]
  };

  std::size_t rows_ = 0;
  std::size_t cols_ = 0;
  MultigridFineSystem fine_;
  SymmetricStencilMatrix fine_stencil_;    // the fine matrix (its free rows) as the smoother reads it
  bool lines_ = true;                      // the fine smoother solves lines
  std::array<LineFactor, 2> line_factor_;  // along rows, along columns (empty without lines_)
  std::vector<Vec3> line_vector_;          // [particles] the lines' right-hand sides and solutions, in line order
  std::vector<Vec3> fine_residual_;        // [particles]
  std::vector<CoarseLevel> coarse_;        // levels 1 .. level_count() - 1
  BandedCholesky coarsest_;                // the last level's matrix, factored
  std::vector<double> coarsest_vector_;
};

}  // namespace clothsim
