#include "integrators/integrator.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#include <utility>

#include "core/assert.h"
#include "integrators/explicit_runge_kutta.h"
#include "integrators/imex.h"
#include "integrators/implicit_euler.h"
#include "integrators/symplectic_euler.h"

namespace clothsim {

std::string_view to_string(IntegratorKind kind) {
  switch (kind) {
    case IntegratorKind::rkf45: return "rkf45";
    case IntegratorKind::rk4: return "rk4";
    case IntegratorKind::symplectic_euler: return "symplectic-euler";
    case IntegratorKind::implicit_euler: return "implicit-euler";
    case IntegratorKind::imex: return "imex";
  }
  return "unknown";
}

std::vector<IntegratorKind> all_integrator_kinds() {
  std::vector<IntegratorKind> kinds;
  for (int value = 0; value < 256; ++value) {
    const auto kind = static_cast<IntegratorKind>(value);
    if (to_string(kind) == "unknown") break;
    kinds.push_back(kind);
  }
  return kinds;
}

bool parse_integrator_kind(std::string_view text, IntegratorKind& kind) {
  for (IntegratorKind candidate : all_integrator_kinds()) {
    if (text == to_string(candidate)) {
      kind = candidate;
      return true;
    }
  }
  return false;
}

void Integrator::transfer_state(StateArchive& archive) {
  std::uint64_t kind_code = static_cast<std::uint64_t>(kind());
  archive.value("integrator.kind", kind_code);
  if (archive.loading() && kind_code != static_cast<std::uint64_t>(kind())) {
    throw std::runtime_error("field 'integrator.kind' is " + std::to_string(kind_code) + ", not " +
                             std::string(to_string(kind())) + "'s " + std::to_string(static_cast<int>(kind())));
  }
  transfer_fields(archive, "integrator", stats_);
}

IntegratorStats combine(const IntegratorStats& earlier, const IntegratorStats& later) {
  IntegratorStats total = later;
  for_each_field_pair(total, earlier, [](std::string_view, auto& field, const auto& before, Tally tally) {
    switch (tally) {
      case Tally::sum: field += before; break;
      case Tally::least: field = std::min(field, before); break;
      case Tally::greatest: field = std::max(field, before); break;
      case Tally::latest: break;
    }
  });
  return total;
}

std::unique_ptr<Integrator> make_integrator(const ClothModel& model, const IntegratorSettings& settings,
                                            const ForceOptions& force_options) {
  CLOTHSIM_ASSERT(force_options.threads >= 1, "thread count is resolved before integrators are made");
  switch (settings.kind) {
    case IntegratorKind::rkf45:
      return std::make_unique<AdaptiveRungeKutta>(model, settings, force_options, kFehlberg45);
    case IntegratorKind::rk4: return std::make_unique<FixedStepRungeKutta>(model, settings, force_options, kClassicRk4);
    case IntegratorKind::symplectic_euler: return std::make_unique<SymplecticEuler>(model, settings, force_options);
    case IntegratorKind::implicit_euler: return std::make_unique<ImplicitEuler>(model, settings, force_options);
    case IntegratorKind::imex: return std::make_unique<AdditiveRungeKutta>(model, settings, force_options);
  }
  return nullptr;
}

}  // namespace clothsim
