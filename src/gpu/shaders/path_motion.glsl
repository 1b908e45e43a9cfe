// A path's motion over an advance from its row (device_step.h, kPathReals), relative to the
// advance's start t0 (tau = t - t0): x(tau) = x0 + v tau + A (sin(theta0 + omega tau) - sin theta0),
// which covers every AnchorPath kind between two path events, written by the host at the advance's
// start (gpu/device_paths.h). The includer reads the row's reals from its own array: anchors'
// (anchor_motion.glsl) or colliders' (obstacle_contacts.comp).
//
// sin and cos are computed here, not by GLSL's built-ins: those exist for float only, and Vulkan
// lets them be 2^-11 off. Cody and Waite's reduction by pi/2 (pi/2 in fdlibm's three parts), then Taylor
// polynomials on |r| <= pi/4 to degree 17 and 16, whose truncation error (below 1e-19) is under
// double's rounding. The host reduces theta0 to [-pi, pi] and an advance spans one frame, so the
// argument stays small and the reduction exact enough.
#ifndef CLOTHSIM_PATH_MOTION_GLSL
#define CLOTHSIM_PATH_MOTION_GLSL

struct SineCosine {
  Real sine;
  Real cosine;
};

SineCosine sine_cosine(Real x) {
  const Real k = floor(x * CLOTHSIM_REAL(0.63661977236758134308) + CLOTHSIM_REAL(0.5));  // 2/pi
  const Real r = ((x - k * CLOTHSIM_REAL(1.57079632673412561417)) - k * CLOTHSIM_REAL(6.07710050630396597660e-11)) -
                 k * CLOTHSIM_REAL(2.02226624879595063154e-21);
  const Real r2 = r * r;
  // Horner forms of sin r = r - r^3/3! + ... + r^17/17! and cos r = 1 - r^2/2! + ... + r^16/16!.
  Real s = CLOTHSIM_REAL(2.81145725434552076e-15);  // 1/17!
  s = s * r2 - CLOTHSIM_REAL(7.64716373181981647e-13);
  s = s * r2 + CLOTHSIM_REAL(1.60590438368216146e-10);
  s = s * r2 - CLOTHSIM_REAL(2.50521083854417188e-8);
  s = s * r2 + CLOTHSIM_REAL(2.75573192239858907e-6);
  s = s * r2 - CLOTHSIM_REAL(1.98412698412698413e-4);
  s = s * r2 + CLOTHSIM_REAL(8.33333333333333333e-3);
  s = s * r2 - CLOTHSIM_REAL(1.66666666666666667e-1);
  s = r + r * r2 * s;
  Real c = CLOTHSIM_REAL(4.77947733238738530e-14);  // 1/16!
  c = c * r2 - CLOTHSIM_REAL(1.14707455977297247e-11);
  c = c * r2 + CLOTHSIM_REAL(2.08767569878680990e-9);
  c = c * r2 - CLOTHSIM_REAL(2.75573192239858907e-7);
  c = c * r2 + CLOTHSIM_REAL(2.48015873015873016e-5);
  c = c * r2 - CLOTHSIM_REAL(1.38888888888888889e-3);
  c = c * r2 + CLOTHSIM_REAL(4.16666666666666667e-2);
  c = c * r2 - CLOTHSIM_REAL(0.5);
  c = CLOTHSIM_REAL(1.0) + r2 * c;
  // Quadrant k mod 4: (sin, cos) of x = r + k pi/2.
  const int quadrant = int(k - CLOTHSIM_REAL(4.0) * floor(k * CLOTHSIM_REAL(0.25)));
  if (quadrant == 0) return SineCosine(s, c);
  if (quadrant == 1) return SineCosine(c, -s);
  if (quadrant == 2) return SineCosine(-s, -c);
  return SineCosine(-c, s);
}

struct PathMotion {
  Vec3 position;
  Vec3 velocity;
  Vec3 acceleration;
};

PathMotion path_motion(Vec3 x0, Vec3 v, Vec3 amplitude, Real omega, Real theta0, Real tau) {
  PathMotion motion;
  motion.position = x0 + v * tau;
  motion.velocity = v;
  motion.acceleration = Vec3(0.0);
  if (omega != Real(0.0)) {
    const SineCosine now = sine_cosine(theta0 + omega * tau);
    const SineCosine start = sine_cosine(theta0);
    motion.position += amplitude * (now.sine - start.sine);
    motion.velocity += amplitude * (omega * now.cosine);
    motion.acceleration = amplitude * (-omega * omega * now.sine);
  }
  return motion;
}

#endif
