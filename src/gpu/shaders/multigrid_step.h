// The layout shared by the V-cycle on the device (gpu/device_multigrid.h) and its shaders
// multigrid_*.comp: the push constants and the phases, read by C++ and by GLSL.
//
// The level arrays hold every level one after another, level 0 (the lattice, one node a particle)
// first: node n of a level starting at `base` is entry base + n. A node's matrix row is
// kStencilSlots 3x3 blocks (integrators/multigrid_stencil.inc), column by column; its vectors
// three Reals. Level 0's right-hand side and solution are the conjugate gradients' residual and
// preconditioned residual, and its smoother's blocks implicit Euler's block Jacobi inverses; its
// entries in `level_rhs`, `level_solution` and `level_diagonal_inverse` are unused.
#if defined(__cplusplus)
#pragma once
#include <cstdint>
namespace clothsim::gpu {
using uint = std::uint32_t;
#define CLOTHSIM_SLOT inline constexpr uint
#else
#define CLOTHSIM_SLOT const uint
#endif

// multigrid_cycle's phases.
CLOTHSIM_SLOT kCycleClear = 0;     // level 0's solution = 0
CLOTHSIM_SLOT kCycleSmooth = 1;    // one colour of a Gauss-Seidel sweep on the level
CLOTHSIM_SLOT kCycleResidual = 2;  // the level's residual rhs - A x
CLOTHSIM_SLOT kCycleRestrict = 3;  // the next level's rhs = P^T residual, its solution = 0
CLOTHSIM_SLOT kCycleProlong = 4;   // x += P (the next level's solution)

// multigrid_lines's phases: level 0's line smoother (with integrator.cg_line_smoother).
CLOTHSIM_SLOT kLinesFactor = 0;  // each line's factor L D L^T along `direction`, one invocation a line
CLOTHSIM_SLOT kLinesRhs = 1;     // the right-hand sides of one colour's lines, the other lines held
CLOTHSIM_SLOT kLinesSolve = 2;   // the lines of one colour along `direction` solved

// multigrid_coarse's phases (one workgroup).
CLOTHSIM_SLOT kCoarseFactor = 0;  // the coarsest level's matrix, dense, factored by Cholesky
CLOTHSIM_SLOT kCoarseCycle = 1;   // the V-cycle from a level of at most kTailNodes nodes down and up

// The colours of the Gauss-Seidel sweeps: node (i, j) has colour 3 (i mod 3) + (j mod 3). No two
// nodes of a colour share a matrix entry (the stencil reaches 2 nodes), so a colour is one pass.
CLOTHSIM_SLOT kSmootherColours = 9;
// The line smoother's colours: line l (a lattice row, or a column) has colour l mod 3. No two lines
// of a colour share a matrix entry, so a colour along one direction is one pass.
CLOTHSIM_SLOT kLineColours = 3;

// LatticeMultigrid's: the coarsest level's nodes at most, solved exactly (3 unknowns a node), and
// the sweeps on each side of a coarse level's correction.
CLOTHSIM_SLOT kCoarsestNodes = 64;
CLOTHSIM_SLOT kCoarsestDofs = 3 * kCoarsestNodes;
CLOTHSIM_SLOT kCoarseSweeps = 1;
// The levels (but the lattice) of at most this many nodes run in one workgroup, the rest of the
// cycle in one pass (multigrid_coarse): passes over them cost more in their start than in their work.
CLOTHSIM_SLOT kTailNodes = 1024;
// multigrid_coarse's workgroup: fixed, the one workgroup that factors, and cycles over the small levels.
CLOTHSIM_SLOT kCoarseWorkgroup = 256;
// The levels at most: a side of 2^16 nodes halves 16 times to one node.
CLOTHSIM_SLOT kMaxLevels = 18;

struct MultigridPassConstants {
  uint phase;           // the pass's phase (above)
  uint level;           // the level it works on (0: the lattice)
  uint base;            // the level's first node in the level arrays
  uint rows;            // the level's nodes in each direction
  uint cols;
  uint next_base;       // the next coarser level's (restriction, prolongation, Galerkin's product)
  uint next_rows;
  uint next_cols;
  uint colour;          // kCycleSmooth, kLinesSolve: the colour swept
  uint direction;       // multigrid_lines: 0 the lattice's rows, 1 its columns
  uint iteration;       // 1: a pass of a CG iteration, which returns at once once the solve has stopped
  uint radial_slot_base;  // multigrid_assemble: the first radial spring's force slot
};

#if defined(__cplusplus)
#undef CLOTHSIM_SLOT
}  // namespace clothsim::gpu
#endif
