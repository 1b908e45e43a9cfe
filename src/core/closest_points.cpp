#include "core/closest_points.h"

#include <algorithm>

namespace clothsim {

TrianglePoint closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a;
  const Vec3 ac = c - a;
  const Vec3 ap = p - a;
  const double d1 = dot(ab, ap);
  const double d2 = dot(ac, ap);
  if (d1 <= 0.0 && d2 <= 0.0) return {a, {1.0, 0.0, 0.0}, TriangleFeature::vertex, 0};
  const Vec3 bp = p - b;
  const double d3 = dot(ab, bp);
  const double d4 = dot(ac, bp);
  if (d3 >= 0.0 && d4 <= d3) return {b, {0.0, 1.0, 0.0}, TriangleFeature::vertex, 1};
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
    const double v = d1 / (d1 - d3);
    return {a + v * ab, {1.0 - v, v, 0.0}, TriangleFeature::edge, 0};
  }
  const Vec3 cp = p - c;
  const double d5 = dot(ab, cp);
  const double d6 = dot(ac, cp);
  if (d6 >= 0.0 && d5 <= d6) return {c, {0.0, 0.0, 1.0}, TriangleFeature::vertex, 2};
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
    const double w = d2 / (d2 - d6);
    return {a + w * ac, {1.0 - w, 0.0, w}, TriangleFeature::edge, 2};
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return {b + w * (c - b), {0.0, 1.0 - w, w}, TriangleFeature::edge, 1};
  }
  const double inverse = 1.0 / (va + vb + vc);
  const double v = vb * inverse;
  const double w = vc * inverse;
  return {a + v * ab + w * ac, {1.0 - v - w, v, w}, TriangleFeature::face, 0};
}

SegmentPoints closest_points_of_segments(const Vec3& p1, const Vec3& q1, const Vec3& p2, const Vec3& q2) {
  // Squared lengths below this are points: the division by them would amplify rounding.
  constexpr double kDegenerate = 1e-30;
  const Vec3 d1 = q1 - p1;
  const Vec3 d2 = q2 - p2;
  const Vec3 r = p1 - p2;
  const double a = dot(d1, d1);
  const double e = dot(d2, d2);
  const double f = dot(d2, r);
  double s = 0.0;
  double t = 0.0;
  if (a <= kDegenerate && e <= kDegenerate) {
    // Both points.
  } else if (a <= kDegenerate) {
    t = std::clamp(f / e, 0.0, 1.0);
  } else {
    const double c = dot(d1, r);
    if (e <= kDegenerate) {
      s = std::clamp(-c / a, 0.0, 1.0);
    } else {
      const double b = dot(d1, d2);
      const double denominator = a * e - b * b;  // >= 0; 0 for parallel segments
      s = denominator > 0.0 ? std::clamp((b * f - c * e) / denominator, 0.0, 1.0) : 0.0;
      t = (b * s + f) / e;
      if (t < 0.0) {
        t = 0.0;
        s = std::clamp(-c / a, 0.0, 1.0);
      } else if (t > 1.0) {
        t = 1.0;
        s = std::clamp((b - c) / a, 0.0, 1.0);
      }
    }
  }
  return {s, t, p1 + s * d1, p2 + t * d2};
}

}  // namespace clothsim
