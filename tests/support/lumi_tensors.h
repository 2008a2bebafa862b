#pragma once
// Lumi-Net tensors in the pass tests: up to the GPU as storage buffers, back as tensors, and
// compared as single-channel images (one row per tensor row) so that RT_REQUIRE_MATCHES applies.
#include <string>
#include <utility>
#include <vector>

#include "passes/common/lumi_tensor.h"
#include "support/gpu_test.h"
#include "support/pass_harness.h"

namespace rt::test {

inline vk::Buffer& input_tensor(PassHarness& gpu, const std::string& name, const passes::LumiTensor& tensor) {
  return gpu.input_buffer(name, tensor.values);
}

inline vk::Buffer& output_tensor(PassHarness& gpu, const std::string& name, uint32_t views, uint32_t channels,
                                 uint32_t width, uint32_t height) {
  return gpu.output_buffer<float>(name, size_t(views) * channels * width * height);
}

inline passes::LumiTensor tensor_of(const PassOutputs& out, const std::string& name, uint32_t views,
                                    uint32_t channels, uint32_t width, uint32_t height) {
  passes::LumiTensor t(views, channels, width, height);
  t.values = out.values<float>(name);
  return t;
}

inline HostImage as_image(const passes::LumiTensor& t) {
  HostImage image(t.width, t.height * t.views * t.channels, PixelFormat::R32F);
  image.texels = t.values;
  return image;
}

// Sizes for the tensor passes: 1x1, a row, a column, odd, not multiples of the 8x8 tile.
inline const std::vector<std::pair<uint32_t, uint32_t>>& lumi_sizes() {
  static const std::vector<std::pair<uint32_t, uint32_t>> sizes = {{1, 1}, {7, 5}, {9, 1}, {1, 13}, {33, 17}, {67, 29}};
  return sizes;
}

}  // namespace rt::test
