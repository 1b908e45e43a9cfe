#version 450
#extension GL_GOOGLE_include_directive : require
// The V-cycle's line smoother on level 0 (gpu/device_multigrid.h), with integrator.cg_line_smoother:
// the CPU's block line Gauss-Seidel (LatticeMultigrid::factor_lines, solve_line), one invocation a
// line. Along `direction` (0: each lattice row, 1: each column):
//   kLinesFactor  each line's matrix, block pentadiagonal (the opposite radial springs reach two
//                 nodes along it), factored as L D L^T node by node along the line: with its blocks
//                 a0 (to itself), a1, a2 (to the nodes 1 and 2 before) and w = a1 - a2 L1(t-1)^T,
//                   L2(t) = a2 D(t-2)^-1,  L1(t) = w D(t-1)^-1,  D(t) = a0 - w L1(t)^T - a2 L2(t)^T;
//                 per node D^-1, L1 and L2 into line_factors (a node outside the system, anchored
//                 or held in every direction, has a zero D^-1 and so a zero solution)
//   kLinesRhs     the lines of one colour, one invocation a node: rhs - A_off x into line_vector,
//                 A_off the blocks to the other lines, which are held (the most of a line's work, in
//                 parallel over its nodes)
//   kLinesSolve   the lines of one colour, one invocation a line: x = A_line^-1 line_vector, L, D and
//                 L^T solved in turn along the line (3 blocks a node)
// The line's blocks are level 0's (multigrid_assemble: filtered in the held directions), those of
// the row the residuals read. A particle held along its normal gets the mean of its solved
// diagonal along that normal, so that its D is invertible; its right-hand side has no part along
// the normal, so neither has its solution. Lines of a colour (kLineColours) share no matrix entry,
// so a pass is one colour; down the V the rows then the columns, colours ascending, up the V the
// reverse, so that the cycle stays symmetric. The CPU visits its lines in bands instead (its
// threads), the same smoother in another order.
#include "gpu/shaders/shared_text.glsl"
#include "gpu/shaders/implicit_step.h"
#include "gpu/shaders/multigrid_step.h"

layout(constant_id = 0) const uint kWorkgroupSize = 64u;  // the workgroup size, specialized by ComputePipeline
layout(local_size_x_id = 0) in;
#include "gpu/shaders/invocation.glsl"

layout(std430, binding = 0) readonly buffer LevelBlocks { float level_blocks[]; };
layout(std430, binding = 1) buffer LineFactors { Real line_factors[]; };  // [2 directions][particles][3][9]
layout(std430, binding = 2) buffer LineVector { Real line_vector[]; };    // [3 particles], a line's L solve
layout(std430, binding = 3) readonly buffer Residual { Real residual[]; };    // [3 particles], CG's r
layout(std430, binding = 4) buffer Preconditioned { Real preconditioned[]; }; // [3 particles], CG's z
layout(std430, binding = 5) readonly buffer ParticleAnchor { int particle_anchor[]; };
layout(std430, binding = 6) readonly buffer Hold { uint hold[]; };
layout(std430, binding = 7) readonly buffer SurfaceContacts { Real surface_contacts[]; };
layout(std430, binding = 8) readonly buffer SolveUint { uint solve_uint[]; };

layout(push_constant) uniform Constants { MultigridPassConstants constants; };

#include "gpu/shaders/held_directions.glsl"
#include "gpu/shaders/multigrid_levels.glsl"

// The factor's blocks of a node: its D^-1, L1 (to the node before) and L2 (to the node two before).
const uint kDiagonalInverse = 0u, kBelow = 1u, kTwoBelow = 2u;

uint factor_index(uint node, uint block) {
  return 27u * (constants.direction * constants.rows * constants.cols + node) + 9u * block;
}
Mat3 factor_block(uint node, uint block) {
  const uint i = factor_index(node, block);
  return Mat3(line_factors[i], line_factors[i + 1], line_factors[i + 2], line_factors[i + 3], line_factors[i + 4],
              line_factors[i + 5], line_factors[i + 6], line_factors[i + 7], line_factors[i + 8]);
}
void set_factor_block(uint node, uint block, Mat3 m) {
  const uint i = factor_index(node, block);
  for (uint column = 0u; column < 3u; ++column) {
    for (uint r = 0u; r < 3u; ++r) line_factors[i + 3u * column + r] = m[column][r];
  }
}

// The line's nodes: how many, and the t-th of line `line`.
uint line_length() { return constants.direction == 0u ? constants.cols : constants.rows; }
uint line_node(uint line, uint t) {
  return constants.direction == 0u ? line * constants.cols + t : t * constants.cols + line;
}
// The stencil slot of the node `before` nodes back along the line.
int slot_before(uint before) {
  return constants.direction == 0u ? stencil_slot(0, -int(before)) : stencil_slot(-int(before), 0);
}
bool on_line(int slot) {
  return constants.direction == 0u ? stencil_row_offset(slot) == 0 : stencil_column_offset(slot) == 0;
}

Vec3 vector3(uint node) {
  return Vec3(line_vector[3u * node], line_vector[3u * node + 1u], line_vector[3u * node + 2u]);
}
void set_vector3(uint node, Vec3 v) {
  for (uint k = 0u; k < 3u; ++k) line_vector[3u * node + k] = v[k];
}
Vec3 fine_solution(uint p) {
  return Vec3(preconditioned[3u * p], preconditioned[3u * p + 1u], preconditioned[3u * p + 2u]);
}

// Node `node`'s block to itself on its line, made invertible along a held normal (above).
Mat3 line_diagonal(uint node) {
  Mat3 block = level_block(node, kStencilDiagonal);
  if (hold[node] == kHoldNormal) {
    const Vec3 n = contact_normal(node);
    block += (Real(0.5) * (block[0][0] + block[1][1] + block[2][2])) * outerProduct(n, n);
  }
  return block;
}

void factor_line(uint line) {
  Mat3 inverse_1 = Mat3(0.0), inverse_2 = Mat3(0.0);  // D^-1 of the nodes 1 and 2 before
  Mat3 below_1 = Mat3(0.0);                            // L1 of the node before
  for (uint t = 0u; t < line_length(); ++t) {
    const uint node = line_node(line, t);
    const Mat3 a1 = t >= 1u ? level_block(node, slot_before(1u)) : Mat3(0.0);
    const Mat3 a2 = t >= 2u ? level_block(node, slot_before(2u)) : Mat3(0.0);
    const Mat3 w = a1 - a2 * transpose(below_1);
    // D's inverses are symmetric, so a D^-1 = a (D^-1)^T.
    const Mat3 two_below = a2 * transpose(inverse_2);
    const Mat3 below = w * transpose(inverse_1);
    const Mat3 d = line_diagonal(node) - w * transpose(below) - a2 * transpose(two_below);
    const Real trace = d[0][0] + d[1][1] + d[2][2];
    const Mat3 d_inverse = trace > Real(0.0) ? inverse(Real(0.5) * (d + transpose(d))) : Mat3(0.0);
    set_factor_block(node, kDiagonalInverse, d_inverse);
    set_factor_block(node, kBelow, below);
    set_factor_block(node, kTwoBelow, two_below);
    inverse_2 = inverse_1;
    inverse_1 = d_inverse;
    below_1 = below;
  }
}

// rhs - A_off x at `node`: its row without the blocks on its own line, in the solved directions.
Vec3 line_rhs(uint node) {
  if (particle_anchor[node] >= 0) return Vec3(0.0);
  const uint i = node / constants.cols;
  const uint j = node % constants.cols;
  Vec3 product = Vec3(0.0);
  for (int s = 0; s < kStencilSlots; ++s) {
    uint q;
    if (!on_line(s) && stencil_neighbour(i, j, s, constants.rows, constants.cols, q)) {
      product += level_block(node, s) * fine_solution(q);
    }
  }
  const Vec3 rhs = Vec3(residual[3u * node], residual[3u * node + 1u], residual[3u * node + 2u]);
  return rhs - held(node, product);
}

void solve_line(uint line) {
  const uint length = line_length();
  Vec3 v_1 = Vec3(0.0), v_2 = Vec3(0.0);  // the L solve's at the nodes 1 and 2 before
  for (uint t = 0u; t < length; ++t) {
    const uint node = line_node(line, t);
    const Vec3 y = vector3(node) - factor_block(node, kBelow) * v_1 - factor_block(node, kTwoBelow) * v_2;
    set_vector3(node, y);
    v_2 = v_1;
    v_1 = y;
  }
  // Back up the line: v_1 and v_2 the solution at the nodes 1 and 2 after, with their L1 and L2.
  v_1 = Vec3(0.0);
  v_2 = Vec3(0.0);
  Mat3 below_1 = Mat3(0.0), two_below_1 = Mat3(0.0), two_below_2 = Mat3(0.0);
  for (uint t = length; t-- > 0u;) {
    const uint node = line_node(line, t);
    const Vec3 z = factor_block(node, kDiagonalInverse) * vector3(node) - transpose(below_1) * v_1 -
                   transpose(two_below_2) * v_2;
    if (particle_anchor[node] < 0) {
      const Vec3 x = held(node, z);
      for (uint k = 0u; k < 3u; ++k) preconditioned[3u * node + k] = x[k];
    }
    v_2 = v_1;
    v_1 = z;
    two_below_2 = two_below_1;
    below_1 = factor_block(node, kBelow);
    two_below_1 = factor_block(node, kTwoBelow);
  }
}

void main() {
  if (constants.iteration != 0u && solve_uint[kSolveDone] != 0u) return;
  const uint k = invocation_index();
  const uint lines = constants.direction == 0u ? constants.rows : constants.cols;
  if (constants.phase == kLinesFactor) {
    if (k < lines) factor_line(k);
  } else if (constants.phase == kLinesRhs) {
    const uint line = constants.colour + kLineColours * (k / line_length());
    if (line < lines) {
      const uint node = line_node(line, k % line_length());
      set_vector3(node, line_rhs(node));
    }
  } else {
    const uint line = constants.colour + kLineColours * k;
    if (line < lines) solve_line(line);
  }
}
