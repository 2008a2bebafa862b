// Bilinear color from an 8-bit storage image with explicit loads, not a sampler: samplers may
// quantise the weights (8 sub-texel bits are allowed), the C++ reference does not.
#ifndef REMOTETOUCH_BILINEAR_GLSL
#define REMOTETOUCH_BILINEAR_GLSL

// GLSL cannot pass a storage image with its format to a function: the including shader names
// its rgba8 image in RT_BILINEAR_IMAGE before including this file.
// `at` in pixel coordinates of the band starting at row `band` (pixel centres at integers);
// clamped to the band's edge.
vec3 bilinear_rgb(vec2 at, int band, ivec2 size) {
  vec2 base = floor(at);
  vec2 f = at - base;
  ivec2 p = ivec2(base);
  ivec2 last = size - 1;
  ivec2 offset = ivec2(0, band);
  vec3 c00 = imageLoad(RT_BILINEAR_IMAGE, clamp(p, ivec2(0), last) + offset).rgb;
  vec3 c10 = imageLoad(RT_BILINEAR_IMAGE, clamp(p + ivec2(1, 0), ivec2(0), last) + offset).rgb;
  vec3 c01 = imageLoad(RT_BILINEAR_IMAGE, clamp(p + ivec2(0, 1), ivec2(0), last) + offset).rgb;
  vec3 c11 = imageLoad(RT_BILINEAR_IMAGE, clamp(p + ivec2(1, 1), ivec2(0), last) + offset).rgb;
  return mix(mix(c00, c10, f.x), mix(c01, c11, f.x), f.y);
}

#endif
