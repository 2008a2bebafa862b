// Lumi-Net's numeric rules, shared by its passes and mirrored by their C++ references. Tests of
// the bit pattern, as in numeric.glsl, because fast-math may fold isnan() to false.
#ifndef REMOTETOUCH_LUMI_NUMERIC_GLSL
#define REMOTETOUCH_LUMI_NUMERIC_GLSL

bool is_nan(float x) { return (floatBitsToUint(x) & 0x7fffffffu) > 0x7f800000u; }
bool is_negative_infinity(float x) { return floatBitsToUint(x) == 0xff800000u; }

// The logistic function without overflow: the clamp keeps exp() finite and changes nothing a
// float can show (the logistic of 88 is already 1 in float).
float safe_sigmoid(float x) {
  x = clamp(x, -88.0, 88.0);
  if (x >= 0.0) return 1.0 / (1.0 + exp(-x));
  const float e = exp(x);
  return e / (1.0 + e);
}

#endif
