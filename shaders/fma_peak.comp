#version 460
#extension GL_GOOGLE_include_directive : require
// The device's arithmetic peak: independent chains of vec4 fused multiply-adds, long enough that
// memory does not count; each invocation writes its sum so that nothing is optimised away. The
// map x -> x * m + n with m < 1 stays bounded whatever the start.
#include "shared/config.h"
#include "common/numeric.glsl"

layout(local_size_x = 64) in;

layout(binding = 0, std430) readonly buffer Seeds { float seeds[]; };
layout(binding = 1, std430) writeonly buffer Sums { float sums[]; };

layout(push_constant) uniform Params { FmaPeakParams params; };

const float kMultiplier = 0.999;
const float kAddend = 0.001;

void main() {
  uint index = gl_GlobalInvocationID.x;
  if (index >= params.invocations) return;
  float seed = seeds[index];
  seed = is_finite(seed) ? clamp(seed, -1.0, 1.0) : 0.0;
  vec4 chain[RT_FMA_CHAINS];
  for (int c = 0; c < RT_FMA_CHAINS; ++c) chain[c] = vec4(seed) + vec4(0.0, 0.125, 0.25, 0.375) * float(c + 1) / float(RT_FMA_CHAINS);
  for (uint i = 0; i < params.iterations; ++i)
    for (int c = 0; c < RT_FMA_CHAINS; ++c) chain[c] = fma(chain[c], vec4(kMultiplier), vec4(kAddend));
  vec4 total = vec4(0.0);
  for (int c = 0; c < RT_FMA_CHAINS; ++c) total += chain[c];
  sums[index] = total.x + total.y + total.z + total.w;
}
