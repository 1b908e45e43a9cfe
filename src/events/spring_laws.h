// The C++ spelling of events/spring_laws.inc: the tearing test, the return mapping of permanent
// stretching and the crease law, the text the Vulkan backend's event passes compile as well.
#pragma once

#include <algorithm>
#include <cmath>

#include "core/shared_text.h"
#include "forces/element.h"

namespace clothsim::spring_laws {

using Real = double;
using element::kStraightAngle;
using std::abs;
using std::clamp;

#include "events/spring_laws.inc"

}  // namespace clothsim::spring_laws
