#include "model/cloth_model.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>
#include <utility>

#include "core/assert.h"
#include "core/error.h"
#include "model/lattice_springs.h"

namespace clothsim {
namespace {

constexpr std::uint32_t kNoConnector = std::numeric_limits<std::uint32_t>::max();

void build_connector_radial_table(ClothModel& model) {
  const std::size_t connectors = model.connector_count();
  std::vector<std::uint32_t> count(connectors + 1, 0);
  for (const auto& pair : model.radial_connectors) {
    ++count[pair[0] + 1];
    ++count[pair[1] + 1];
  }
  for (std::size_t e = 0; e < connectors; ++e) count[e + 1] += count[e];
  model.connector_radial_offset = count;
  model.radial_of_connector.assign(count.back(), 0);
  std::vector<std::uint32_t> cursor(count.begin(), count.end() - 1);
  for (std::size_t r = 0; r < model.radial_count(); ++r) {
    for (std::uint32_t e : model.radial_connectors[r])
      model.radial_of_connector[cursor[e]++] = static_cast<std::uint32_t>(r);
  }
}

}  // namespace

void finish_model(ClothModel& model) {
  constexpr double kNever = std::numeric_limits<double>::infinity();
  const std::size_t connectors = model.connector_count();
  const std::size_t radials = model.radial_count();
  if (model.connector_live.size() != connectors) model.connector_live.assign(connectors, 1);
  if (model.connector_break_time.size() != connectors) model.connector_break_time.assign(connectors, kNever);
  if (model.connector_original_length.size() != connectors)
    model.connector_original_length = model.connector_rest_length;
  if (model.connector_break_strain.size() != connectors) model.connector_break_strain.assign(connectors, kNever);
  if (model.connector_yield_strain.size() != connectors) model.connector_yield_strain.assign(connectors, kNever);
  if (model.radial_live.size() != radials) model.radial_live.assign(radials, 1);
  if (model.radial_original_angle.size() != radials) model.radial_original_angle = model.radial_rest_angle;
  if (model.radial_yield_angle.size() != radials) model.radial_yield_angle.assign(radials, kNever);
  model.broken_connector_count =
      static_cast<std::size_t>(std::count(model.connector_live.begin(), model.connector_live.end(), std::uint8_t{0}));
  build_connector_radial_table(model);
}

namespace {

template <typename T>
std::size_t vector_bytes(const std::vector<T>& v) {
  return v.capacity() * sizeof(T);
}

// Bytes of an array of `count` elements of the model's member `member` (its element type).
template <auto kMember>
constexpr std::size_t array_bytes(std::size_t count) {
  using Vector = std::remove_reference_t<decltype(std::declval<ClothModel>().*kMember)>;
  return count * sizeof(typename Vector::value_type);
}

}  // namespace

std::size_t ClothModel::bytes() const {
  return vector_bytes(particle_mass) + vector_bytes(particle_inverse_mass) + vector_bytes(particle_anchor) +
         vector_bytes(particle_rest_position) + vector_bytes(connector_particles) +
         vector_bytes(connector_rest_length) + vector_bytes(connector_stiffness) + vector_bytes(connector_damping) +
         vector_bytes(connector_live) + vector_bytes(connector_break_time) + vector_bytes(connector_original_length) +
         vector_bytes(connector_break_strain) + vector_bytes(connector_yield_strain) + vector_bytes(radial_particles) +
         vector_bytes(radial_connectors) + vector_bytes(radial_kind) + vector_bytes(radial_rest_angle) +
         vector_bytes(radial_stiffness) + vector_bytes(radial_damping) + vector_bytes(radial_live) +
         vector_bytes(radial_original_angle) + vector_bytes(radial_yield_angle) +
         vector_bytes(connector_radial_offset) + vector_bytes(radial_of_connector) + vector_bytes(anchors);
}

LatticeCounts lattice_counts(std::size_t rows, std::size_t cols) {
  LatticeCounts counts;
  counts.rows = rows;
  counts.cols = cols;
  counts.particles = rows * cols;
  if (rows == 0 || cols == 0) return counts;
  counts.connectors = rows * (cols - 1) + (rows - 1) * cols;
  counts.radials = 4 * (rows - 1) * (cols - 1) + rows * (cols >= 2 ? cols - 2 : 0) + cols * (rows >= 2 ? rows - 2 : 0);
  return counts;
}

std::size_t lattice_model_bytes(const LatticeCounts& counts, std::size_t anchors) {
  using M = ClothModel;
  const std::size_t n = counts.particles;
  const std::size_t e = counts.connectors;
  const std::size_t r = counts.radials;
  return array_bytes<&M::particle_mass>(n) + array_bytes<&M::particle_inverse_mass>(n) +
         array_bytes<&M::particle_anchor>(n) + array_bytes<&M::particle_rest_position>(n) +
         array_bytes<&M::connector_particles>(e) + array_bytes<&M::connector_rest_length>(e) +
         array_bytes<&M::connector_stiffness>(e) + array_bytes<&M::connector_damping>(e) +
         array_bytes<&M::connector_live>(e) + array_bytes<&M::connector_break_time>(e) +
         array_bytes<&M::connector_original_length>(e) + array_bytes<&M::connector_break_strain>(e) +
         array_bytes<&M::connector_yield_strain>(e) + array_bytes<&M::radial_particles>(r) +
         array_bytes<&M::radial_connectors>(r) + array_bytes<&M::radial_kind>(r) +
         array_bytes<&M::radial_rest_angle>(r) + array_bytes<&M::radial_stiffness>(r) +
         array_bytes<&M::radial_damping>(r) + array_bytes<&M::radial_live>(r) +
         array_bytes<&M::radial_original_angle>(r) + array_bytes<&M::radial_yield_angle>(r) +
         array_bytes<&M::connector_radial_offset>(e + 1) + array_bytes<&M::radial_of_connector>(2 * r) +
         array_bytes<&M::anchors>(anchors);
}

std::size_t count_pieces(const ClothModel& model) {
  // Union-find with path halving over the intact connectors.
  std::vector<std::uint32_t> parent(model.particle_count());
  for (std::size_t p = 0; p < parent.size(); ++p) parent[p] = static_cast<std::uint32_t>(p);
  const auto root = [&](std::uint32_t p) {
    while (parent[p] != p) p = parent[p] = parent[parent[p]];
    return p;
  };
  for (std::size_t e = 0; e < model.connector_count(); ++e) {
    if (model.connector_live[e] == 0) continue;
    const auto [a, b] = model.connector_particles[e];
    parent[root(a)] = root(b);
  }
  std::size_t pieces = 0;
  for (std::size_t p = 0; p < parent.size(); ++p) pieces += root(static_cast<std::uint32_t>(p)) == p ? 1 : 0;
  return pieces;
}

std::string ClothModel::describe_particle(std::size_t particle) const {
  std::string text = "particle " + std::to_string(particle);
  if (cols > 0 && particle < particle_count()) {
    text += " (row " + std::to_string(particle / static_cast<std::size_t>(cols)) + ", col " +
            std::to_string(particle % static_cast<std::size_t>(cols)) + ")";
  }
  return text;
}

ClothModel build_lattice(const LatticeDef& lattice, const Environment& environment, std::span<const Anchor> anchors,
                         const std::string& source) {
  if (lattice.rows < 1 || lattice.cols < 1 || lattice.rows * static_cast<long long>(lattice.cols) < 2) {
    throw InputError(source, "lattice", "needs at least 2 particles (rows >= 1, cols >= 1)");
  }
  if (!(lattice.spacing > 0.0) || !(lattice.particle_mass > 0.0)) {
    throw InputError(source, "lattice", "spacing and particle mass must be positive");
  }

  ClothModel model;
  model.rows = lattice.rows;
  model.cols = lattice.cols;
  model.spacing = lattice.spacing;
  model.layout = ModelLayout::lattice;
  model.environment = environment;

  const int rows = lattice.rows;
  const int cols = lattice.cols;
  const std::size_t n = static_cast<std::size_t>(rows) * static_cast<std::size_t>(cols);
  model.particle_mass.assign(n, lattice.particle_mass);
  model.particle_inverse_mass.assign(n, 1.0 / lattice.particle_mass);
  model.particle_anchor.assign(n, -1);
  model.particle_rest_position.resize(n);
  for (int i = 0; i < rows; ++i) {
    for (int j = 0; j < cols; ++j) {
      model.particle_rest_position[lattice_index(cols, i, j)] = {(j - (cols - 1) / 2.0) * lattice.spacing, 0.0,
                                                                 (i - (rows - 1) / 2.0) * lattice.spacing};
    }
  }

  // Every array at its final size from the start: growing by push_back would leave up to twice
  // the memory in capacity, and copy each array as it grows (docs/performance.md, "Memory").
  const LatticeCounts counts = lattice_counts(static_cast<std::size_t>(rows), static_cast<std::size_t>(cols));
  model.connector_particles.reserve(counts.connectors);
  model.connector_rest_length.reserve(counts.connectors);
  model.connector_stiffness.reserve(counts.connectors);
  model.connector_damping.reserve(counts.connectors);
  model.radial_particles.reserve(counts.radials);
  model.radial_connectors.reserve(counts.radials);
  model.radial_kind.reserve(counts.radials);
  model.radial_rest_angle.reserve(counts.radials);
  model.radial_stiffness.reserve(counts.radials);
  model.radial_damping.reserve(counts.radials);

  // The springs in the lattice's order (model/lattice_springs.h): every connector, then every
  // radial spring between two of a particle's connectors. neighbour_connector[p][arm] is the
  // connector from p along arm, or kNoConnector at the border.
  std::vector<std::array<std::uint32_t, 4>> neighbour_connector(
      n, {kNoConnector, kNoConnector, kNoConnector, kNoConnector});
  const auto grid_cols = static_cast<std::size_t>(cols);
  for_each_lattice_spring(
      static_cast<std::size_t>(rows), grid_cols,
      [&](std::uint32_t e, std::uint32_t p, bool south) {
        const int arm = south ? 1 : 0;
        const std::uint32_t b = lattice_neighbour(p, arm, grid_cols);
        model.connector_particles.push_back({p, b});
        model.connector_rest_length.push_back(lattice.spacing);
        model.connector_stiffness.push_back(lattice.connector.stiffness);
        model.connector_damping.push_back(lattice.connector.damping);
        neighbour_connector[p][static_cast<std::size_t>(arm)] = e;
        neighbour_connector[b][static_cast<std::size_t>(arm + 2)] = e;
        return true;
      },
      [&](std::uint32_t, std::uint32_t p, std::size_t pair) {
        const int arm_b = kRadialArmB[pair];
        const int arm_c = kRadialArmC[pair];
        const bool adjacent = !radial_pair_is_opposite(pair);
        model.radial_particles.push_back(
            {p, lattice_neighbour(p, arm_b, grid_cols), lattice_neighbour(p, arm_c, grid_cols)});
        model.radial_connectors.push_back({neighbour_connector[p][static_cast<std::size_t>(arm_b)],
                                           neighbour_connector[p][static_cast<std::size_t>(arm_c)]});
        model.radial_kind.push_back(adjacent ? RadialKind::adjacent : RadialKind::opposite);
        model.radial_rest_angle.push_back(adjacent ? lattice.adjacent_rest_angle : lattice.opposite_rest_angle);
        model.radial_stiffness.push_back(adjacent ? lattice.adjacent.stiffness : lattice.opposite.stiffness);
        model.radial_damping.push_back(adjacent ? lattice.adjacent.damping : lattice.opposite.damping);
        return true;
      });

  model.anchors.reserve(anchors.size());
  for (const Anchor& anchor : anchors) {
    if (anchor.particle >= n) {
      throw InputError(source, "anchors",
                       "particle index " + std::to_string(anchor.particle) + " is outside the lattice [0, " +
                           std::to_string(n - 1) + "]");
    }
    if (model.particle_anchor[anchor.particle] >= 0) {
      throw InputError(source, "anchors", model.describe_particle(anchor.particle) + " is anchored twice");
    }
    model.particle_anchor[anchor.particle] = static_cast<std::int32_t>(model.anchors.size());
    model.particle_inverse_mass[anchor.particle] = 0.0;
    model.anchors.push_back(anchor);
  }

  CLOTHSIM_ASSERT(model.connector_count() == counts.connectors && model.radial_count() == counts.radials,
                  "lattice_counts() counts what build_lattice() makes");
  finish_model(model);
  return model;
}

ClothState make_rest_state(const ClothModel& model) {
  ClothState state;
  state.position = model.particle_rest_position;
  state.velocity.assign(model.particle_count(), Vec3{});
  for (const Anchor& anchor : model.anchors) {
    state.position[anchor.particle] = anchor.path.position(0.0);
    state.velocity[anchor.particle] = anchor.path.velocity_at(0.0);
  }
  return state;
}

}  // namespace clothsim
