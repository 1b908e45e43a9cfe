#include "collision/sheet_elements.h"

#include "core/assert.h"

namespace clothsim {
namespace {

constexpr std::uint32_t kNone = 0xFFFFFFFFu;

// The connector from each particle to its right (i, j+1) and lower (i+1, j) neighbour, or kNone.
struct LatticeConnectors {
  std::vector<std::uint32_t> right;
  std::vector<std::uint32_t> down;
};

LatticeConnectors lattice_connectors(const ClothModel& model) {
  const std::size_t n = model.particle_count();
  const auto cols = static_cast<std::uint32_t>(model.cols);
  LatticeConnectors lattice{std::vector<std::uint32_t>(n, kNone), std::vector<std::uint32_t>(n, kNone)};
  for (std::size_t e = 0; e < model.connector_count(); ++e) {
    auto [a, b] = model.connector_particles[e];
    if (a > b) std::swap(a, b);
    if (b == a + 1 && b % cols != 0) lattice.right[a] = static_cast<std::uint32_t>(e);
    if (b == a + cols) lattice.down[a] = static_cast<std::uint32_t>(e);
  }
  return lattice;
}

bool intact(const ClothModel& model, std::uint32_t connector) {
  return connector != kNone && model.connector_live[connector] != 0;
}

}  // namespace

void refresh_sheet_elements(const ClothModel& model, SheetElements& elements) {
  if (elements.built_particles == model.particle_count() && elements.built_broken == model.broken_connector_count) {
    return;
  }
  CLOTHSIM_ASSERT(static_cast<std::size_t>(model.rows) * static_cast<std::size_t>(model.cols) == model.particle_count(),
                  "self-collision needs the rows x cols lattice");
  const LatticeConnectors lattice = lattice_connectors(model);
  elements.triangle.clear();
  elements.edge.clear();
  for (std::size_t e = 0; e < model.connector_count(); ++e) {
    if (model.connector_live[e] != 0) elements.edge.push_back(model.connector_particles[e]);
  }
  const auto cols = static_cast<std::uint32_t>(model.cols);
  for (std::uint32_t i = 0; i + 1 < static_cast<std::uint32_t>(model.rows); ++i) {
    for (std::uint32_t j = 0; j + 1 < cols; ++j) {
      const std::uint32_t p00 = i * cols + j;  // (i, j)
      const std::uint32_t p01 = p00 + 1;       // (i, j+1)
      const std::uint32_t p10 = p00 + cols;    // (i+1, j)
      const std::uint32_t p11 = p10 + 1;       // (i+1, j+1)
      const bool upper = intact(model, lattice.down[p00]) && intact(model, lattice.right[p00]);
      const bool lower = intact(model, lattice.down[p01]) && intact(model, lattice.right[p10]);
      if (upper) elements.triangle.push_back({p00, p10, p01});
      if (lower) elements.triangle.push_back({p01, p10, p11});
      if (upper || lower) elements.edge.push_back({p10, p01});
    }
  }
  elements.built_particles = model.particle_count();
  elements.built_broken = model.broken_connector_count;
}

SheetElementCounts sheet_element_counts(const LatticeCounts& counts) {
  const std::size_t cells = counts.rows > 0 && counts.cols > 0 ? (counts.rows - 1) * (counts.cols - 1) : 0;
  return {2 * cells, counts.connectors + cells};
}

}  // namespace clothsim
