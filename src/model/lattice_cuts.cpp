#include "model/lattice_cuts.h"

#include <algorithm>
#include <cmath>

namespace clothsim {
namespace {

using Point = std::array<double, 2>;

// (b - a) x (c - a): > 0 when c is left of a->b.
double orientation(const Point& a, const Point& b, const Point& c) {
  return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

bool on_segment(const Point& a, const Point& b, const Point& c) {
  return std::min(a[0], b[0]) <= c[0] && c[0] <= std::max(a[0], b[0]) && std::min(a[1], b[1]) <= c[1] &&
         c[1] <= std::max(a[1], b[1]);
}

// Whether segments p1-p2 and q1-q2 share a point (the textbook orientation test, with the
// collinear cases).
bool segments_cross(const Point& p1, const Point& p2, const Point& q1, const Point& q2) {
  const double d1 = orientation(q1, q2, p1);
  const double d2 = orientation(q1, q2, p2);
  const double d3 = orientation(p1, p2, q1);
  const double d4 = orientation(p1, p2, q2);
  if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0))) return true;
  return (d1 == 0 && on_segment(q1, q2, p1)) || (d2 == 0 && on_segment(q1, q2, p2)) ||
         (d3 == 0 && on_segment(p1, p2, q1)) || (d4 == 0 && on_segment(p1, p2, q2));
}

}  // namespace

std::vector<std::uint32_t> connectors_crossed(const ClothModel& model, std::span<const std::array<double, 2>> point,
                                              const std::array<double, 2>& from, const std::array<double, 2>& to) {
  std::vector<std::uint32_t> crossed;
  for (std::size_t e = 0; e < model.connector_count(); ++e) {
    if (model.connector_live[e] == 0) continue;
    const auto [a, b] = model.connector_particles[e];
    const Point& pa = point[a];
    const Point& pb = point[b];
    if (std::isnan(pa[0]) || std::isnan(pb[0])) continue;
    if (segments_cross(pa, pb, from, to)) crossed.push_back(static_cast<std::uint32_t>(e));
  }
  return crossed;
}

std::vector<std::uint32_t> connectors_crossed_in_lattice(const ClothModel& model, const std::array<double, 2>& from,
                                                         const std::array<double, 2>& to) {
  std::vector<Point> lattice(model.particle_count());
  const auto cols = static_cast<std::size_t>(std::max(model.cols, 1));
  for (std::size_t p = 0; p < lattice.size(); ++p) {
    lattice[p] = {static_cast<double>(p / cols), static_cast<double>(p % cols)};
  }
  return connectors_crossed(model, lattice, from, to);
}

}  // namespace clothsim
