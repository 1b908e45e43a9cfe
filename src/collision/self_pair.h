// Self-collision's pair geometry for the CPU: the shared text collision/self_pair.inc (a pair's
// distance, normal and weights, the bound on how fast the distance changes along a motion, and the
// first touch along it), with the nearest points it reads (core/closest_points.inc), compiled in
// double. The self pass (collision/self_contacts.h) calls it; the device compiles the same text.
#pragma once

#include <algorithm>
#include <cmath>

#include "core/shared_text.h"
#include "core/vec3.h"

namespace clothsim::self_pair {

using Real = double;
using std::clamp;
using std::max;
using std::min;
using std::sqrt;
#include "core/closest_points.inc"
// The pair geometry reads the nearest points above.
#include "collision/self_pair.inc"

}  // namespace clothsim::self_pair
