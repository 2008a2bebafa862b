// Reproducible per-pixel random numbers: a PCG hash of (x, y, seed), the same bits in GLSL and
// in the C++ references (passes/random_reference.h), so simulated noise can be tested exactly.
#ifndef REMOTETOUCH_RANDOM_GLSL
#define REMOTETOUCH_RANDOM_GLSL

uint pcg_hash(uint value) {
  uint state = value * 747796405u + 2891336453u;
  uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
  return (word >> 22u) ^ word;
}

uint pixel_hash(ivec2 pixel, uint seed, uint stream) {
  return pcg_hash(pcg_hash(pcg_hash(uint(pixel.x) ^ (stream * 0x9E3779B9u)) ^ uint(pixel.y)) ^ seed);
}

// Uniform in (0, 1): 24 bits, exact in float, never 0 (the logarithm below needs that).
float uniform01(uint bits) { return (float(bits >> 8u) + 0.5) * (1.0 / 16777216.0); }

// A standard normal sample (Box-Muller).
float normal01(ivec2 pixel, uint seed) {
  float u1 = uniform01(pixel_hash(pixel, seed, 1u));
  float u2 = uniform01(pixel_hash(pixel, seed, 2u));
  return sqrt(-2.0 * log(u1)) * cos(6.28318530718 * u2);
}

#endif
