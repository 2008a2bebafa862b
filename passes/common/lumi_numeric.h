#pragma once
// The C++ side of shaders/common/lumi_numeric.glsl, written independently of the GLSL.
#include <algorithm>
#include <cmath>

namespace rt::passes {

inline float lumi_safe_sigmoid(float x) {
  x = std::clamp(x, -88.0f, 88.0f);
  if (x >= 0.0f) return 1.0f / (1.0f + std::exp(-x));
  const float e = std::exp(x);
  return e / (1.0f + e);
}

}  // namespace rt::passes
