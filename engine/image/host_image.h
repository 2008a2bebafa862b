#pragma once
// An image in CPU memory: what tests, references, file I/O and uploads exchange. Texels are
// floats whatever the GPU format (8-bit formats hold values in [0, 1]), row-major, channels
// interleaved. No Vulkan here: CPU modules own no Vulkan objects.
#include <cstdint>
#include <string>
#include <vector>

namespace rt {

// R16U holds integers 0..65535 (depth in millimetres); D32F is a depth attachment (metres or
// the projection's depth, as the pass says).
enum class PixelFormat { R32F, RGBA32F, RGBA8, R16U, D32F };

uint32_t channel_count(PixelFormat format);
uint32_t bytes_per_texel(PixelFormat format);
const char* format_name(PixelFormat format);

struct HostImage {
  uint32_t width = 0;
  uint32_t height = 0;
  PixelFormat format = PixelFormat::RGBA32F;
  std::vector<float> texels;

  HostImage() = default;
  HostImage(uint32_t width, uint32_t height, PixelFormat format, float fill = 0.0f);

  uint32_t channels() const { return channel_count(format); }
  size_t index(uint32_t x, uint32_t y, uint32_t channel = 0) const {
    return (size_t(y) * width + x) * channels() + channel;
  }
  float& at(uint32_t x, uint32_t y, uint32_t channel = 0) { return texels[index(x, y, channel)]; }
  float at(uint32_t x, uint32_t y, uint32_t channel = 0) const { return texels[index(x, y, channel)]; }
};

// Packs into the GPU's byte layout for `format` (8-bit channels rounded to nearest) and back.
std::vector<std::byte> pack_texels(const HostImage& image);
HostImage unpack_texels(uint32_t width, uint32_t height, PixelFormat format, const std::byte* data);

}  // namespace rt
