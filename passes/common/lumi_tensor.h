#pragma once
// The host side of the Lumi-Net passes' tensors (shaders/shared/lumi_net.h): views as the batch,
// then channels, rows, columns (NCHW), floats. The references read and write these; the passes
// take GPU buffers holding the same bytes.
#include <cstddef>
#include <cstdint>
#include <random>
#include <vector>

namespace rt::passes {

struct LumiTensor {
  uint32_t views = 0, channels = 0, width = 0, height = 0;
  std::vector<float> values;

  LumiTensor() = default;
  LumiTensor(uint32_t views_, uint32_t channels_, uint32_t width_, uint32_t height_, float fill = 0.0f)
      : views(views_), channels(channels_), width(width_), height(height_),
        values(size_t(views_) * channels_ * width_ * height_, fill) {}

  size_t index(uint32_t v, uint32_t c, uint32_t x, uint32_t y) const {
    return ((size_t(v) * channels + c) * height + y) * width + x;
  }
  float& at(uint32_t v, uint32_t c, uint32_t x, uint32_t y) { return values[index(v, c, x, y)]; }
  float at(uint32_t v, uint32_t c, uint32_t x, uint32_t y) const { return values[index(v, c, x, y)]; }
  size_t size_bytes() const { return values.size() * sizeof(float); }
};

inline LumiTensor random_lumi_tensor(std::mt19937& rng, uint32_t views, uint32_t channels, uint32_t width,
                                     uint32_t height, float low = -1.0f, float high = 1.0f) {
  LumiTensor t(views, channels, width, height);
  std::uniform_real_distribution<float> value(low, high);
  for (float& v : t.values) v = value(rng);
  return t;
}

}  // namespace rt::passes
