#pragma once
// Small numeric rules the C++ references share with the shaders (shaders/common/numeric.glsl),
// written here independently of the GLSL.
#include <algorithm>
#include <cmath>

namespace rt::passes {

// A value in [0, 1]; anything non-finite (NaN, +-Inf) counts as 0.
inline float unit_or_zero(float x) { return std::isfinite(x) ? std::min(std::max(x, 0.0f), 1.0f) : 0.0f; }

}  // namespace rt::passes
