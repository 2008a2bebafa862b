#pragma once
// The C++ side of shaders/common/random.glsl: the same bits for the same pixel and seed.
#include <cmath>
#include <cstdint>

namespace rt::passes {

inline uint32_t pcg_hash(uint32_t value) {
  const uint32_t state = value * 747796405u + 2891336453u;
  const uint32_t word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
  return (word >> 22u) ^ word;
}

inline uint32_t pixel_hash(int x, int y, uint32_t seed, uint32_t stream) {
  return pcg_hash(pcg_hash(pcg_hash(uint32_t(x) ^ (stream * 0x9E3779B9u)) ^ uint32_t(y)) ^ seed);
}

inline float uniform01(uint32_t bits) { return (float(bits >> 8u) + 0.5f) * (1.0f / 16777216.0f); }

inline float normal01(int x, int y, uint32_t seed) {
  const float u1 = uniform01(pixel_hash(x, y, seed, 1u));
  const float u2 = uniform01(pixel_hash(x, y, seed, 2u));
  return std::sqrt(-2.0f * std::log(u1)) * std::cos(6.28318530718f * u2);
}

}  // namespace rt::passes
