// The element factors as implicit Euler's passes read them back (implicit_linearize.comp writes
// them; the layout is implicit_step.h's), and the products and diagonal blocks they make, the
// blocks forces/element_jacobian.h forms on the CPU:
//   a connector's  (k_s K_e + d_s C_e) w,  K_e = along u u^T + across (I - u u^T),  C_e = damping u u^T;
//   a radial spring's row i of k_s K + d_s C over its particles' vectors (V_0, V_1, V_2):
//     (k_s in_plane + d_s damping) g_i (sum_j g_j . V_j) + k_s P (equal s_i S + opposite d_i D),
//     S = sum_j s_j V_j,  D = sum_j d_j V_j.
// The includer declares the arrays connector_factors and radial_factors.
#ifndef CLOTHSIM_IMPLICIT_FACTORS_GLSL
#define CLOTHSIM_IMPLICIT_FACTORS_GLSL

ConnectorLinearization load_connector(uint e) {
  const uint base = kConnectorFactorReals * e;
  ConnectorLinearization f;
  f.direction = Vec3(connector_factors[base], connector_factors[base + 1], connector_factors[base + 2]);
  f.along = connector_factors[base + 3];
  f.across = connector_factors[base + 4];
  f.damping = connector_factors[base + 5];
  return f;
}

Vec3 radial_vector(uint index) {
  return Vec3(radial_factors[index], radial_factors[index + 1], radial_factors[index + 2]);
}

RadialLinearization load_radial(uint r) {
  const uint base = kRadialFactorReals * r;
  RadialLinearization f;
  f.gradient_a = radial_vector(base);
  f.gradient_b = radial_vector(base + 3);
  f.gradient_c = radial_vector(base + 6);
  f.in_plane_stiffness = radial_factors[base + 9];
  f.damping = radial_factors[base + 10];
  f.transverse_axis = radial_vector(base + 11);
  f.straight = radial_factors[base + 14] != Real(0.0);
  f.sum_tilt = radial_vector(base + 15);
  f.difference_tilt = radial_vector(base + 18);
  f.equal_coupling = radial_factors[base + 21];
  f.opposite_coupling = radial_factors[base + 22];
  return f;
}

// (k_s K_e + d_s C_e) w: the product's part on particle a for w = V_a - V_b (on b it is the negative).
Vec3 connector_product(ConnectorLinearization f, Real stiffness_scale, Real damping_scale, Vec3 w) {
  const Vec3 u = f.direction;
  const Real along_w = dot(u, w);
  return (stiffness_scale * f.along + damping_scale * f.damping) * along_w * u +
         (stiffness_scale * f.across) * (w - along_w * u);
}

// The diagonal block of the same on a or b (the off-diagonal blocks are its negative).
Mat3 connector_diagonal(ConnectorLinearization f, Real stiffness_scale, Real damping_scale) {
  const Mat3 along = outerProduct(f.direction, f.direction);
  return (stiffness_scale * f.along + damping_scale * f.damping) * along +
         (stiffness_scale * f.across) * (Mat3(1.0) - along);
}

// P w: the transverse projector of the radial factors.
Vec3 transverse_projection(RadialLinearization f, Vec3 w) {
  const Vec3 a = f.transverse_axis;
  return f.straight ? w - dot(a, w) * a : dot(a, w) * a;
}

Mat3 transverse_projector(RadialLinearization f) {
  const Mat3 axis = outerProduct(f.transverse_axis, f.transverse_axis);
  return f.straight ? Mat3(1.0) - axis : axis;
}

Vec3 radial_gradient(RadialLinearization f, uint i) {
  return i == 0u ? f.gradient_a : (i == 1u ? f.gradient_b : f.gradient_c);
}

// The block (i, j) of k_s K + d_s C: the coefficient of V_j in row i.
Mat3 radial_block(RadialLinearization f, uint i, uint j, Real stiffness_scale, Real damping_scale) {
  const Real coupling =
      f.equal_coupling * f.sum_tilt[i] * f.sum_tilt[j] + f.opposite_coupling * f.difference_tilt[i] * f.difference_tilt[j];
  return (stiffness_scale * f.in_plane_stiffness + damping_scale * f.damping) *
             outerProduct(radial_gradient(f, i), radial_gradient(f, j)) +
         (stiffness_scale * coupling) * transverse_projector(f);
}

// The diagonal block (i, i).
Mat3 radial_diagonal(RadialLinearization f, uint i, Real stiffness_scale, Real damping_scale) {
  return radial_block(f, i, i, stiffness_scale, damping_scale);
}

#endif
