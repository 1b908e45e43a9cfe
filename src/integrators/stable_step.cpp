#include "integrators/stable_step.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

namespace clothsim {

StableStep estimate_stable_step(const ClothModel& model, IntegratorKind kind) {
  StableStep result;
  result.step = std::numeric_limits<double>::infinity();
  double oscillation_limit = 0.0;  // h omega at the stability boundary
  double decay_limit = 0.0;        // h gamma at the stability boundary
  switch (kind) {
    case IntegratorKind::rk4:
      oscillation_limit = 2.83;
      decay_limit = 2.79;
      break;
    case IntegratorKind::symplectic_euler:
      oscillation_limit = 2.0;
      decay_limit = 2.0;
      break;
    case IntegratorKind::rkf45:
    case IntegratorKind::implicit_euler:
    case IntegratorKind::imex: return result;
  }
  const std::size_t n = model.particle_count();
  // Gershgorin row sums of the stiffness and damping matrices (N/m, N s/m): sum_j |A_ij|.
  std::vector<double> stiffness(n, 0.0);
  std::vector<double> damping(n, 0.0);
  for (std::size_t e = 0; e < model.connector_count(); ++e) {
    if (model.connector_live[e] == 0) continue;
    // k (u u^T) on the diagonal block and -k (u u^T) off it: a row sum of 2 k.
    for (std::uint32_t p : model.connector_particles[e]) {
      stiffness[p] += 2.0 * model.connector_stiffness[e];
      damping[p] += 2.0 * model.connector_damping[e];
    }
  }
  for (std::size_t r = 0; r < model.radial_count(); ++r) {
    if (model.radial_live[r] == 0) continue;
    const auto [centre, b, c] = model.radial_particles[r];
    // At rest the angle spring's Hessian is k g g^T, g the angle's gradient: 1/L on each arm's end,
    // at most 1/L_b + 1/L_c on the centre. Row i sums to k |g_i| (|g_b| + |g_c| + |g_centre|).
    const double arm_b = norm(model.particle_rest_position[b] - model.particle_rest_position[centre]);
    const double arm_c = norm(model.particle_rest_position[c] - model.particle_rest_position[centre]);
    if (arm_b <= 0.0 || arm_c <= 0.0) continue;
    const double g_b = 1.0 / arm_b;
    const double g_c = 1.0 / arm_c;
    const double g_centre = g_b + g_c;
    const double total = g_b + g_c + g_centre;
    for (const auto& [p, g] : {std::pair{centre, g_centre}, std::pair{b, g_b}, std::pair{c, g_c}}) {
      stiffness[p] += model.radial_stiffness[r] * g * total;
      damping[p] += model.radial_damping[r] * g * total;
    }
  }
  for (std::size_t p = 0; p < n; ++p) {
    if (model.is_anchored(p) || !(model.particle_mass[p] > 0.0)) continue;
    const double omega = std::sqrt(stiffness[p] / model.particle_mass[p]);  // rad/s
    const double gamma = damping[p] / model.particle_mass[p];               // 1/s
    const double step = std::min(omega > 0.0 ? oscillation_limit / omega : result.step,
                                 gamma > 0.0 ? decay_limit / gamma : result.step);
    if (step < result.step) {
      result.step = step;
      result.particle = p;
    }
  }
  return result;
}

}  // namespace clothsim
