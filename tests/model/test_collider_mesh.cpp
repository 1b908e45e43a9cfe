// Mesh colliders (model/collider.h): the signed distance of a closed triangle
// mesh against the exact shapes it approximates. A cube mesh is the box
// exactly, so distances and normals must agree to rounding at random points
// inside and outside, near edges and corners included; an icosphere is the
// sphere to within its chord error.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <memory>
#include <random>
#include <vector>

#include "model/collider.h"
#include "model/mesh_fixtures.h"

namespace clothsim {
namespace {

// An icosahedron subdivided `levels` times, its vertices pushed onto the
// sphere.
std::shared_ptr<const TriangleMesh> icosphere_mesh(const Vec3& center, double radius, int levels) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Vec3> unit = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                            {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
  for (Vec3& p : unit) p = p / norm(p);
  std::vector<std::array<std::uint32_t, 3>> faces = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                                     {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                                     {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                                     {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (int level = 0; level < levels; ++level) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> middle;
    const auto midpoint = [&](std::uint32_t i, std::uint32_t j) {
      const auto key = std::pair{std::min(i, j), std::max(i, j)};
      if (const auto found = middle.find(key); found != middle.end()) return found->second;
      const Vec3 m = unit[i] + unit[j];
      unit.push_back(m / norm(m));
      return middle[key] = static_cast<std::uint32_t>(unit.size() - 1);
    };
    std::vector<std::array<std::uint32_t, 3>> finer;
    for (const auto& [a, b, c] : faces) {
      const std::uint32_t ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
      finer.insert(finer.end(), {{a, ab, ca}, {b, bc, ab}, {c, ca, bc}, {ab, bc, ca}});
    }
    faces = std::move(finer);
  }
  TriangleMesh mesh;
  for (const Vec3& p : unit) mesh.vertex.push_back(center + radius * p);
  for (const auto& face : faces) add_triangle(mesh, face, center);
  prepare_triangle_mesh(mesh);
  return std::make_shared<const TriangleMesh>(std::move(mesh));
}

TEST(ColliderMesh, CubeMeshMatchesTheBoxEverywhere) {
  Collider box;
  box.shape = ColliderShape::box;
  box.center = {0.2, -0.1, 0.3};
  box.half_extents = {0.5, 0.25, 0.4};
  Collider mesh;
  mesh.shape = ColliderShape::mesh;
  mesh.mesh = cube_mesh(box.center, box.half_extents);
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> coordinate(-1.2, 1.2);
  int inside = 0;
  for (int i = 0; i < 2000; ++i) {
    const Vec3 x = box.center + Vec3{coordinate(random), coordinate(random), coordinate(random)};
    const SurfaceDistance expected = signed_distance(box, x, 0.0);
    const SurfaceDistance got = signed_distance(mesh, x, 0.0);
    ASSERT_NEAR(got.distance, expected.distance, 1e-12) << "point " << x.x << " " << x.y << " " << x.z;
    // Inside, points equidistant from two faces have two right normals; skip
    // those ties.
    std::array<double, 3> gaps = {box.half_extents.x - std::abs(x.x - box.center.x),
                                  box.half_extents.y - std::abs(x.y - box.center.y),
                                  box.half_extents.z - std::abs(x.z - box.center.z)};
    std::sort(gaps.begin(), gaps.end());
    const bool tie = expected.distance < 0.0 && gaps[1] - gaps[0] < 1e-9;
    if (!tie) {
      EXPECT_NEAR(norm(got.normal - expected.normal), 0.0, 1e-9);
    }
    inside += expected.distance < 0.0;
  }
  EXPECT_GT(inside, 50);  // the sample reaches inside as well
}

TEST(ColliderMesh, CornersAndEdgesAreSignedByPseudonormals) {
  Collider mesh;
  mesh.shape = ColliderShape::mesh;
  mesh.mesh = cube_mesh({0, 0, 0}, {1, 1, 1});
  // Just outside a corner and an edge, where the nearest face's normal alone
  // may give the wrong sign, and just inside them.
  EXPECT_NEAR(signed_distance(mesh, {1.01, 1.01, 1.01}, 0.0).distance, std::sqrt(3.0) * 0.01, 1e-12);
  EXPECT_NEAR(signed_distance(mesh, {1.01, 1.01, 0.3}, 0.0).distance, std::sqrt(2.0) * 0.01, 1e-12);
  EXPECT_NEAR(signed_distance(mesh, {0.99, 0.98, 0.97}, 0.0).distance, -0.01, 1e-12);
  // On the surface: distance 0, normal the face's.
  const SurfaceDistance on_face = signed_distance(mesh, {1.0, 0.2, 0.1}, 0.0);
  EXPECT_NEAR(on_face.distance, 0.0, 1e-15);
  EXPECT_NEAR(on_face.normal.x, 1.0, 1e-12);
}

TEST(ColliderMesh, IcosphereApproximatesTheSphere) {
  Collider sphere;
  sphere.shape = ColliderShape::sphere;
  sphere.center = {0.0, 0.5, 0.0};
  sphere.radius = 0.3;
  Collider mesh;
  mesh.shape = ColliderShape::mesh;
  mesh.mesh = icosphere_mesh(sphere.center, sphere.radius, 3);
  // Level 3: edges of about 0.14 rad, so a face's centre lies about r (1 - cos 0.08) ~ 0.003 r
  // inside the sphere (the subdivided faces are not all equilateral: a margin).
  const double tolerance = 0.005 * sphere.radius;
  std::mt19937_64 random(11);
  std::uniform_real_distribution<double> coordinate(-0.6, 0.6);
  for (int i = 0; i < 300; ++i) {
    const Vec3 x = sphere.center + Vec3{coordinate(random), coordinate(random), coordinate(random)};
    const SurfaceDistance expected = signed_distance(sphere, x, 0.0);
    const SurfaceDistance got = signed_distance(mesh, x, 0.0);
    ASSERT_NEAR(got.distance, expected.distance, tolerance);
    if (std::abs(expected.distance) > 0.05) {
      EXPECT_GT(dot(got.normal, expected.normal), 0.99);
    }
  }
}

// The hierarchy finds the same nearest triangle as visiting every one (the oracle), on a bumpy
// closed mesh of 5120 triangles, at points near the surface and far from it.
TEST(ColliderMesh, HierarchyAgreesWithBruteForce) {
  TriangleMesh bumpy = *icosphere_mesh({0.1, 0.2, 0.3}, 0.5, 4);
  std::mt19937_64 random(5);
  std::uniform_real_distribution<double> bump(0.9, 1.1);
  for (Vec3& v : bumpy.vertex) v = Vec3{0.1, 0.2, 0.3} + bump(random) * (v - Vec3{0.1, 0.2, 0.3});
  prepare_triangle_mesh(bumpy);
  ASSERT_EQ(bumpy.triangle.size(), 5120u);
  Collider mesh;
  mesh.shape = ColliderShape::mesh;
  mesh.mesh = std::make_shared<const TriangleMesh>(bumpy);
  for (const double reach : {0.6, 3.0}) {
    std::uniform_real_distribution<double> coordinate(-reach, reach);
    for (int i = 0; i < 300; ++i) {
      const Vec3 x{coordinate(random), coordinate(random), coordinate(random)};
      const SurfaceDistance expected = mesh_distance_brute_force(bumpy, x);
      const SurfaceDistance got = signed_distance(mesh, x, 0.0);
      ASSERT_EQ(got.distance, expected.distance) << "point " << x.x << " " << x.y << " " << x.z;
      EXPECT_NEAR(norm(got.normal - expected.normal), 0.0, 1e-12);
    }
  }
}

// A box is skipped only when farther than the best triangle by more than rounding. Here a sliver's
// nearest point to x, computed on one of its edges, lies 1e-16 m outside its own box, so it is
// nearer than its box's distance as computed, which is also the exact distance of four triangles
// meeting at the box's top corner, visited first. Skipping the box when merely as far as them
// (as the traversal did until a fuzz run found it) returned their distance, one unit in the last
// place above the thin triangle's, where the search over every triangle returns the least.
TEST(ColliderMesh, HierarchyFindsATriangleThatRoundingPutsBeyondItsBox) {
  TriangleMesh mesh;
  const Vec3 top{0.79928721379418843, 0.94170030792588055, 0.11586461863460351};
  mesh.vertex = {top,
                 {-0.79025818328130681, -0.75896653928966096, -0.48283254199342729},
                 {-0.17165911817973378, -0.097122645389906254, -0.24984005377568277}};
  mesh.triangle.push_back({0, 1, 2});  // a sliver: its third corner 8e-7 m from the line of the others
  for (std::uint32_t k = 0; k < 4; ++k) {
    const auto first = static_cast<std::uint32_t>(mesh.vertex.size());
    mesh.vertex.push_back(top + Vec3{-2.0 - 0.1 * k, -1.0, 0.3});
    mesh.vertex.push_back(top + Vec3{-2.0 - 0.1 * k, -1.0, -0.3});
    mesh.triangle.push_back({0, first, first + 1});
  }
  prepare_triangle_mesh(mesh);
  // Straight above the top corner: every triangle's box is as far as the corner.
  const Vec3 x{top.x, 1.695937914099352, top.z};
  Collider collider;
  collider.shape = ColliderShape::mesh;
  collider.mesh = std::make_shared<const TriangleMesh>(mesh);
  const double least = mesh_distance_brute_force(mesh, x).distance;
  const double to_corner = x.y - top.y;
  ASSERT_LT(std::abs(least), to_corner);  // the sliver, nearer by rounding
  EXPECT_EQ(signed_distance(collider, x, 0.0).distance, least);
}

TEST(ColliderMesh, MovesAlongItsPath) {
  Collider mesh;
  mesh.shape = ColliderShape::mesh;
  mesh.mesh = cube_mesh({0, 0, 0}, {1, 1, 1});
  mesh.path.kind = AnchorPathKind::linear;
  mesh.path.velocity = {0.0, 2.0, 0.0};
  const SurfaceDistance moved = signed_distance(mesh, {0.0, 3.5, 0.0}, 1.0);  // the top at y = 3
  EXPECT_NEAR(moved.distance, 0.5, 1e-12);
  EXPECT_NEAR(moved.velocity.y, 2.0, 1e-12);
}

}  // namespace
}  // namespace clothsim
