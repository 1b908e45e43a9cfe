// integrators/held_directions.h's filter on the device: v with the directions the step holds on
// particle p removed (none, its contact normal, or all three). The includer declares the arrays
// hold (kHold* per particle) and surface_contacts (kContactReals per particle, the normal first).
#ifndef CLOTHSIM_HELD_DIRECTIONS_GLSL
#define CLOTHSIM_HELD_DIRECTIONS_GLSL

Vec3 contact_normal(uint p) {
  const uint i = kContactReals * p;
  return Vec3(surface_contacts[i], surface_contacts[i + 1], surface_contacts[i + 2]);
}

Vec3 held(uint p, Vec3 v) {
  const uint how = hold[p];
  if (how == kHoldNone) return v;
  if (how == kHoldAll) return Vec3(0.0);
  const Vec3 n = contact_normal(p);
  return v - dot(v, n) * n;
}

#endif
