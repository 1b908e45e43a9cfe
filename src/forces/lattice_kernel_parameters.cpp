// The lattice kernel's preparation and parameters: whether a model has the lattice layout, the
// scratch it needs, and the per-spring values it reads (one per family on a uniform sheet). The
// design is in lattice_kernel.h; the vector loops are in lattice_kernel.cpp.
#include <algorithm>
#include <array>

#include "core/assert.h"
#include "forces/element.h"
#include "forces/forces.h"
#include "forces/lattice_kernel.h"
#include "forces/lattice_kernel_layout.h"

namespace clothsim {

using namespace lattice_layout;

bool LatticeKernel::prepare(const ClothModel& model, Precision precision, bool both_precisions) {
  active_ = false;
  std::vector<double>().swap(scratch64_);
  std::vector<float>().swap(scratch32_);
  precision_ = precision;
  if (model.layout != ModelLayout::lattice || model.rows < 1 || model.cols < 1 ||
      static_cast<std::size_t>(model.rows) * static_cast<std::size_t>(model.cols) != model.particle_count()) {
    return false;
  }
  const auto rows = static_cast<std::size_t>(model.rows);
  const auto cols = static_cast<std::size_t>(model.cols);
  const std::size_t n = model.particle_count();
  // The layout says the springs are the lattice's, in build_lattice()'s order; the check here
  // costs one pass and keeps a model that was edited by hand (and no longer matches its layout)
  // off the kernel. refresh() then finds each spring's place by walking the lattice again.
  const LatticeCounts counts = lattice_counts(rows, cols);
  if (model.connector_count() != counts.connectors || model.radial_count() != counts.radials) return false;
  const bool matches = for_each_lattice_spring(
      rows, cols,
      [&](std::uint32_t e, std::uint32_t p, bool south) {
        const std::array<std::uint32_t, 2> expected{p, lattice_neighbour(p, south ? 1 : 0, cols)};
        return model.connector_particles[e] == expected;
      },
      [&](std::uint32_t r, std::uint32_t p, std::size_t pair) {
        const std::array<std::uint32_t, 3> expected{p, lattice_neighbour(p, kRadialArmB[pair], cols),
                                                    lattice_neighbour(p, kRadialArmC[pair], cols)};
        return model.radial_particles[r] == expected;
      });
  if (!matches) return false;
  rows_ = model.rows;
  cols_ = model.cols;
  padding_ = padding(cols);
  stride_ = stride(n, cols);
  // The parameter arrays only where the sheet is not uniform or a law can make it so.
  const std::size_t arrays = !is_uniform(model) || model.limits.changes_sheet() ? kArrayCount : kUniformArrayCount;
  resize_scratch(arrays);
  if (both_precisions) {
    resize_scratch(precision == Precision::float64 ? Precision::float32 : Precision::float64, arrays);
  }
  block_power_.assign(deterministic_sum_blocks(n), 0.0);
  active_ = true;
  refresh(model);
  return true;
}

void LatticeKernel::set_precision(const ClothModel& model, Precision precision) {
  CLOTHSIM_ASSERT(active_, "set_precision() switches a prepared kernel");
  if (precision == precision_) return;
  const std::size_t arrays = scratch_size() / stride_;
  precision_ = precision;
  resize_scratch(arrays);
  // A uniform sheet's family values are doubles in either precision (and evaluate() takes them
  // again when the revision moves); only the parameter arrays need their copy in this precision.
  if (!uniform_) refresh(model);
}

std::size_t LatticeKernel::bytes_for(const LatticeCounts& counts, bool parameter_arrays, Precision precision) {
  return array_bytes_for(counts, parameter_arrays, precision) +
         deterministic_sum_blocks(counts.particles) * sizeof(double);
}

std::size_t LatticeKernel::array_bytes_for(const LatticeCounts& counts, bool parameter_arrays, Precision precision) {
  const std::size_t arrays = parameter_arrays ? kArrayCount : kUniformArrayCount;
  return arrays * stride(counts.particles, counts.cols) * real_size(precision);
}

void LatticeKernel::resize_scratch(std::size_t arrays) { resize_scratch(precision_, arrays); }

void LatticeKernel::resize_scratch(Precision precision, std::size_t arrays) {
  if (precision == Precision::float64) {
    scratch64_.resize(arrays * stride_, 0.0);
  } else {
    scratch32_.resize(arrays * stride_, 0.0f);
  }
}

bool LatticeKernel::is_uniform(const ClothModel& model) {
  if (model.connector_count() == 0 || model.broken_connector_count != 0) return false;
  std::array<FamilyValues, 3> family{};
  std::array<bool, 3> seen{};
  const auto same = [&](std::size_t f, const FamilyValues& values) {
    if (!seen[f]) {
      seen[f] = true;
      family[f] = values;
    }
    return family[f] == values;
  };
  for (std::size_t e = 0; e < model.connector_count(); ++e) {
    if (model.connector_live[e] == 0 ||
        !same(0, {model.connector_stiffness[e], model.connector_damping[e], model.connector_rest_length[e],
                  model.connector_original_length[e]})) {
      return false;
    }
  }
  for (std::size_t r = 0; r < model.radial_count(); ++r) {
    const std::size_t f = model.radial_kind[r] == RadialKind::adjacent ? 1 : 2;
    if (model.radial_live[r] == 0 ||
        !same(f, {model.radial_stiffness[r], model.radial_damping[r], model.radial_rest_angle[r]})) {
      return false;
    }
  }
  return true;
}

void LatticeKernel::refresh(const ClothModel& model) {
  revision_ = model.revision;
  const bool arrays = scratch_size() == kArrayCount * stride_;
  uniform_ = !arrays && is_uniform(model);
  if (uniform_) {
    family_[0] = {model.connector_stiffness[0], model.connector_damping[0], model.connector_rest_length[0],
                  model.connector_original_length[0]};
    for (std::size_t r = 0; r < model.radial_count(); ++r) {
      const std::size_t f = model.radial_kind[r] == RadialKind::adjacent ? 1 : 2;
      family_[f] = {model.radial_stiffness[r], model.radial_damping[r], model.radial_rest_angle[r]};
    }
    return;
  }
  // A uniform sheet made non-uniform by a live edit: the parameter arrays now, kept from then on
  // (see the top of lattice_kernel.h).
  if (!arrays) resize_scratch(kArrayCount);
  if (precision_ == Precision::float64) {
    copy_parameters<double>(model);
  } else {
    copy_parameters<float>(model);
  }
}

template <typename Real>
void LatticeKernel::copy_parameters(const ClothModel& model) {
  std::vector<Real>& scratch = this->scratch<Real>();
  Real* base = scratch.data() + padding_;
  const auto array = [&](std::size_t a) { return base + a * stride_; };
  const auto real = [](double value) { return static_cast<Real>(value); };
  // Missing springs (borders) keep zeros: no stiffness, no damping, not live.
  std::fill(scratch.begin() + static_cast<std::ptrdiff_t>(kEastStiffness * stride_), scratch.end(), Real(0));
  for_each_lattice_spring(
      static_cast<std::size_t>(rows_), static_cast<std::size_t>(cols_),
      [&](std::uint32_t e, std::uint32_t p, bool south) {
        const std::size_t first = south ? kSouthStiffness : kEastStiffness;
        array(first)[p] = real(model.connector_stiffness[e]);
        array(first + 1)[p] = real(model.connector_damping[e]);
        array(first + 2)[p] = real(model.connector_rest_length[e]);
        array(first + 3)[p] = model.connector_live[e] != 0 ? Real(1) : Real(0);
        array(first + 4)[p] = real(element::kRadialFadeFraction * model.connector_original_length[e]);
        return true;
      },
      [&](std::uint32_t r, std::uint32_t p, std::size_t pair) {
        const bool live = model.radial_live[r] != 0;
        array(kRadialStiffness + pair)[p] = live ? real(model.radial_stiffness[r]) : Real(0);
        array(kRadialDamping + pair)[p] = live ? real(model.radial_damping[r]) : Real(0);
        array(kRadialRestAngle + pair)[p] = real(model.radial_rest_angle[r]);
        return true;
      });
}

}  // namespace clothsim
