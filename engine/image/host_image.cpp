#include "image/host_image.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>

namespace rt {

uint32_t channel_count(PixelFormat format) {
  switch (format) {
    case PixelFormat::R32F: return 1;
    case PixelFormat::RGBA32F: return 4;
    case PixelFormat::RGBA8: return 4;
    case PixelFormat::R16U: return 1;
    case PixelFormat::D32F: return 1;
  }
  throw std::logic_error("unknown pixel format");
}

uint32_t bytes_per_texel(PixelFormat format) {
  switch (format) {
    case PixelFormat::R32F: return 4;
    case PixelFormat::RGBA32F: return 16;
    case PixelFormat::RGBA8: return 4;
    case PixelFormat::R16U: return 2;
    case PixelFormat::D32F: return 4;
  }
  throw std::logic_error("unknown pixel format");
}

const char* format_name(PixelFormat format) {
  switch (format) {
    case PixelFormat::R32F: return "r32f";
    case PixelFormat::RGBA32F: return "rgba32f";
    case PixelFormat::RGBA8: return "rgba8";
    case PixelFormat::R16U: return "r16ui";
    case PixelFormat::D32F: return "d32f";
  }
  return "unknown";
}

HostImage::HostImage(uint32_t width_, uint32_t height_, PixelFormat format_, float fill)
    : width(width_), height(height_), format(format_), texels(size_t(width_) * height_ * channel_count(format_), fill) {}

std::vector<std::byte> pack_texels(const HostImage& image) {
  if (image.texels.size() != size_t(image.width) * image.height * image.channels())
    throw std::invalid_argument("host image holds " + std::to_string(image.texels.size()) + " values, expected " +
                                std::to_string(size_t(image.width) * image.height * image.channels()));
  std::vector<std::byte> bytes(size_t(image.width) * image.height * bytes_per_texel(image.format));
  if (image.format == PixelFormat::RGBA8) {
    for (size_t i = 0; i < image.texels.size(); ++i) {
      const float value = std::isnan(image.texels[i]) ? 0.0f : std::clamp(image.texels[i], 0.0f, 1.0f);
      bytes[i] = std::byte(uint8_t(std::lround(value * 255.0f)));
    }
  } else if (image.format == PixelFormat::R16U) {
    for (size_t i = 0; i < image.texels.size(); ++i) {
      const float value = std::isnan(image.texels[i]) ? 0.0f : std::clamp(image.texels[i], 0.0f, 65535.0f);
      const uint16_t word = uint16_t(std::lround(value));
      std::memcpy(&bytes[2 * i], &word, 2);
    }
  } else {
    std::memcpy(bytes.data(), image.texels.data(), bytes.size());
  }
  return bytes;
}

HostImage unpack_texels(uint32_t width, uint32_t height, PixelFormat format, const std::byte* data) {
  HostImage image(width, height, format);
  if (format == PixelFormat::RGBA8) {
    for (size_t i = 0; i < image.texels.size(); ++i) image.texels[i] = float(uint8_t(data[i])) / 255.0f;
  } else if (format == PixelFormat::R16U) {
    for (size_t i = 0; i < image.texels.size(); ++i) {
      uint16_t word = 0;
      std::memcpy(&word, &data[2 * i], 2);
      image.texels[i] = float(word);
    }
  } else {
    std::memcpy(image.texels.data(), data, image.texels.size() * sizeof(float));
  }
  return image;
}

}  // namespace rt
