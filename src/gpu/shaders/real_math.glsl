// Real-precision helpers the element formulas need and GLSL does not have: norm, and atan2 in
// double precision (GLSL's atan is defined for float only, and Vulkan allows it 4096 ulp).
//
// atan2 is fdlibm's (Sun Microsystems, 1993: e_atan2.c and s_atan.c, "error < 1 ulp"), for
// finite arguments, in Real precision: float shaders run the same polynomial, so their accuracy
// does not depend on the driver's atan either. The CPU's std::atan2 (glibc) differs from it by at
// most an ulp or so, which is the one deliberate difference between the two in double precision.

Real norm(Vec3 v) { return sqrt(dot(v, v)); }

bool sign_bit(Real value) {
#if CLOTHSIM_FLOAT64
  return (unpackDouble2x32(value).y >> 31) != 0u;
#else
  return (floatBitsToUint(value) >> 31) != 0u;
#endif
}

// atan(a) for a >= 0: argument reduction to |t| < 7/16 around atan(1/2), atan(1), atan(3/2),
// atan(inf), then an odd polynomial of degree 23.
Real atan_nonnegative(Real a) {
  const Real atan_high[4] = Real[4](CLOTHSIM_REAL(4.63647609000806093515e-01), CLOTHSIM_REAL(7.85398163397448278999e-01),
                                    CLOTHSIM_REAL(9.82793723247329054082e-01), CLOTHSIM_REAL(1.57079632679489655800e+00));
  const Real atan_low[4] = Real[4](CLOTHSIM_REAL(2.26987774529616870924e-17), CLOTHSIM_REAL(3.06161699786838301793e-17),
                                   CLOTHSIM_REAL(1.39033110312309984516e-17), CLOTHSIM_REAL(6.12323399573676603587e-17));
  if (a >= CLOTHSIM_REAL(7.3786976294838206464e19)) return atan_high[3] + atan_low[3];  // 2^66
  int id = -1;
  Real t = a;
  if (a < CLOTHSIM_REAL(0.4375)) {
    if (a < CLOTHSIM_REAL(7.450580596923828125e-9)) return a;  // 2^-27: atan(a) = a to the last bit
  } else if (a < CLOTHSIM_REAL(1.1875)) {
    if (a < CLOTHSIM_REAL(0.6875)) {
      id = 0;
      t = (CLOTHSIM_REAL(2.0) * a - CLOTHSIM_REAL(1.0)) / (CLOTHSIM_REAL(2.0) + a);
    } else {
      id = 1;
      t = (a - CLOTHSIM_REAL(1.0)) / (a + CLOTHSIM_REAL(1.0));
    }
  } else if (a < CLOTHSIM_REAL(2.4375)) {
    id = 2;
    t = (a - CLOTHSIM_REAL(1.5)) / (CLOTHSIM_REAL(1.0) + CLOTHSIM_REAL(1.5) * a);
  } else {
    id = 3;
    t = CLOTHSIM_REAL(-1.0) / a;
  }
  const Real z = t * t;
  const Real w = z * z;
  const Real s1 =
      z * (CLOTHSIM_REAL(3.33333333333329318027e-01) +
           w * (CLOTHSIM_REAL(1.42857142725034663711e-01) +
                w * (CLOTHSIM_REAL(9.09088713343650656196e-02) +
                     w * (CLOTHSIM_REAL(6.66107313738753120669e-02) +
                          w * (CLOTHSIM_REAL(4.97687799461593236017e-02) + w * CLOTHSIM_REAL(1.62858201153657823623e-02))))));
  const Real s2 = w * (CLOTHSIM_REAL(-1.99999999998764832476e-01) +
                       w * (CLOTHSIM_REAL(-1.11111104054623557880e-01) +
                            w * (CLOTHSIM_REAL(-7.69187620504482999495e-02) +
                                 w * (CLOTHSIM_REAL(-5.83357013379057348645e-02) +
                                      w * CLOTHSIM_REAL(-3.65315727442169155270e-02)))));
  if (id < 0) return t - t * (s1 + s2);
  return atan_high[id] - ((t * (s1 + s2) - atan_low[id]) - t);
}

// atan2(y, x) in [-pi, pi] for finite y and x, signed zeros as in C.
Real atan2(Real y, Real x) {
  const Real pi = CLOTHSIM_REAL(3.1415926535897931160e+00);
  const Real pi_low = CLOTHSIM_REAL(1.2246467991473531772e-16);
  const Real half_pi = CLOTHSIM_REAL(1.5707963267948965580e+00);
  const bool y_negative = sign_bit(y);
  const bool x_negative = sign_bit(x);
  const Real ay = abs(y);
  const Real ax = abs(x);
  if (ay == CLOTHSIM_REAL(0.0)) return x_negative ? (y_negative ? -pi : pi) : y;
  if (ax == CLOTHSIM_REAL(0.0)) return y_negative ? -half_pi : half_pi;
  const Real quotient = ay / ax;
  Real z;
  if (quotient > CLOTHSIM_REAL(1.152921504606846976e18)) {  // 2^60: |y/x| beyond the polynomial's reach
    z = half_pi + CLOTHSIM_REAL(0.5) * pi_low;
  } else if (x_negative && quotient < CLOTHSIM_REAL(8.67361737988403547206e-19)) {  // 2^-60
    z = CLOTHSIM_REAL(0.0);
  } else {
    z = atan_nonnegative(quotient);
  }
  if (x_negative) z = pi - (z - pi_low);
  return y_negative ? -z : z;
}
