// Numerically safe helpers. Tests of the bit pattern, not isnan()/isinf(): drivers may compile
// with fast-math assumptions under which isnan() folds to false.
#ifndef REMOTETOUCH_NUMERIC_GLSL
#define REMOTETOUCH_NUMERIC_GLSL

bool is_finite(float x) {
  return (floatBitsToUint(x) & 0x7f800000u) != 0x7f800000u;
}

// A value in [0, 1]; anything non-finite (NaN, +-Inf) counts as 0.
float unit_or_zero(float x) {
  return is_finite(x) ? clamp(x, 0.0, 1.0) : 0.0;
}

vec3 unit_or_zero(vec3 v) {
  return vec3(unit_or_zero(v.x), unit_or_zero(v.y), unit_or_zero(v.z));
}

#endif
