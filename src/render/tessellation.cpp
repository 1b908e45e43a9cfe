// The renderer's CPU-built triangles (tessellation.h).
#include "render/tessellation.h"

#include <array>
#include <cmath>
#include <numbers>
#include <utility>

namespace clothsim::render {
namespace {

constexpr double kPi = std::numbers::pi;

// Collider triangles: position and normal per vertex (6 floats), three vertices per triangle,
// counter-clockwise seen from outside. Shapes are tessellated finely enough that a sphere of a
// third of the picture looks round (48 x 24); this runs per frame, but for a few colliders it is
// far below the sheet's cost.
struct ColliderTriangles {
  std::vector<float>& out;
  void vertex(const Vec3& position, const Vec3& normal) {
    push_vec3(out, position);
    push_vec3(out, normal);
  }
  void flat(const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 normal = unit_or(cross(b - a, c - a), {0, 1, 0});
    vertex(a, normal);
    vertex(b, normal);
    vertex(c, normal);
  }
  // A sphere of `radius` around the segment from `bottom` to `top` along the unit `axis`, with
  // `side` and `front` completing a right-handed frame (side x front = axis; perpendicular_frame()),
  // which makes the triangles below counter-clockwise from outside: the upper hemisphere at `top`, the lower at
  // `bottom`, and the cylinder between them (a sphere when top == bottom).
  void capsule(const Vec3& bottom, const Vec3& top, double radius, const Vec3& axis, const Vec3& side,
               const Vec3& front) {
    constexpr int kSlices = 48;
    constexpr int kStacks = 24;  // even: the equator is a ring, drawn once at each end
    const auto point = [&](int ring, int slice) {
      // Rings 0..kStacks/2 on the top hemisphere, kStacks/2 + 1..kStacks + 1 on the bottom one
      // (ring kStacks/2 + 1 is the equator again, at the bottom end).
      const int stack = ring <= kStacks / 2 ? ring : ring - 1;
      const double polar = kPi * stack / kStacks;
      const double around = 2.0 * kPi * slice / kSlices;
      const Vec3 normal =
          std::cos(polar) * axis + std::sin(polar) * (std::cos(around) * side + std::sin(around) * front);
      return std::pair{(ring <= kStacks / 2 ? top : bottom) + radius * normal, normal};
    };
    for (int ring = 0; ring <= kStacks; ++ring) {
      for (int slice = 0; slice < kSlices; ++slice) {
        const auto p00 = point(ring, slice), p01 = point(ring, slice + 1);
        const auto p10 = point(ring + 1, slice), p11 = point(ring + 1, slice + 1);
        for (const auto& [position, normal] : {p00, p10, p01, p01, p10, p11}) vertex(position, normal);
      }
    }
  }
};

// The frame of a unit axis: two unit vectors perpendicular to it and to each other.
std::pair<Vec3, Vec3> perpendicular_frame(const Vec3& axis) {
  const Vec3 helper = std::abs(axis.y) < 0.9 ? Vec3{0, 1, 0} : Vec3{1, 0, 0};
  const Vec3 side = unit_or(cross(helper, axis), {1, 0, 0});
  return {side, cross(axis, side)};
}

}  // namespace

Vec3 unit_or(const Vec3& v, const Vec3& fallback) {
  const double length = norm(v);
  return length > 1e-12 && std::isfinite(length) ? v / length : fallback;
}

void make_sphere(int slices, int stacks, std::vector<float>& vertices, std::vector<std::uint32_t>& indices) {
  for (int i = 0; i <= stacks; ++i) {
    const double polar = kPi * i / stacks;
    for (int j = 0; j <= slices; ++j) {
      const double around = 2.0 * kPi * j / slices;
      push_vec3(vertices,
                Vec3{std::sin(polar) * std::cos(around), std::cos(polar), std::sin(polar) * std::sin(around)});
    }
  }
  const auto index = [slices](int i, int j) { return static_cast<std::uint32_t>(i * (slices + 1) + j); };
  for (int i = 0; i < stacks; ++i) {
    for (int j = 0; j < slices; ++j) {
      // Counter-clockwise seen from outside, so gl_FrontFacing holds on the visible side.
      indices.insert(indices.end(), {index(i, j), index(i, j + 1), index(i + 1, j)});
      indices.insert(indices.end(), {index(i, j + 1), index(i + 1, j + 1), index(i + 1, j)});
    }
  }
}

void append_collider(const Collider& collider, const Vec3& shift, const Vec3& focus, double plane_extent,
                     std::vector<float>& out) {
  ColliderTriangles triangles{out};
  switch (collider.shape) {
    case ColliderShape::plane: {
      const Vec3 normal = unit_or(collider.normal, {0, 1, 0});
      const Vec3 point = collider.point + shift;
      const Vec3 centre = focus - dot(focus - point, normal) * normal;
      const auto [u, v] = perpendicular_frame(normal);
      const Vec3 a = centre + plane_extent * (-u - v), b = centre + plane_extent * (u - v);
      const Vec3 c = centre + plane_extent * (u + v), d = centre + plane_extent * (-u + v);
      for (const Vec3& p : {a, b, c, a, c, d}) triangles.vertex(p, normal);
      break;
    }
    case ColliderShape::sphere: {
      const Vec3 centre = collider.center + shift;
      const auto [side, front] = perpendicular_frame({0, 1, 0});
      triangles.capsule(centre, centre, collider.radius, {0, 1, 0}, side, front);
      break;
    }
    case ColliderShape::capsule: {
      const Vec3 axis = unit_or(collider.b - collider.a, {0, 1, 0});
      const auto [side, front] = perpendicular_frame(axis);
      triangles.capsule(collider.a + shift, collider.b + shift, collider.radius, axis, side, front);
      break;
    }
    case ColliderShape::box: {
      const Vec3 centre = collider.center + shift;
      const Vec3& h = collider.half_extents;
      const auto corner = [&](int i) {
        return centre + Vec3{(i & 1 ? 1 : -1) * h.x, (i & 2 ? 1 : -1) * h.y, (i & 4 ? 1 : -1) * h.z};
      };
      // Each face's corners counter-clockwise seen from outside (bit 0: +x, bit 1: +y, bit 2: +z).
      constexpr std::array<std::array<int, 4>, 6> kFaces = {
          {{1, 3, 7, 5}, {0, 4, 6, 2}, {2, 6, 7, 3}, {0, 1, 5, 4}, {4, 5, 7, 6}, {0, 2, 3, 1}}};
      for (const auto& face : kFaces) {
        triangles.flat(corner(face[0]), corner(face[1]), corner(face[2]));
        triangles.flat(corner(face[0]), corner(face[2]), corner(face[3]));
      }
      break;
    }
    case ColliderShape::mesh:
      if (collider.mesh == nullptr) break;
      for (const auto& [a, b, c] : collider.mesh->triangle) {
        triangles.flat(collider.mesh->vertex[a] + shift, collider.mesh->vertex[b] + shift,
                       collider.mesh->vertex[c] + shift);
      }
      break;
  }
}

bool is_floor(const Collider& collider) { return collider.shape == ColliderShape::plane && collider.normal.y > 0.999; }

}  // namespace clothsim::render
