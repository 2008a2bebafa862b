#include "net/image_codec.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <opencv2/imgcodecs.hpp>
#include <stdexcept>

namespace rt::net {
namespace {

uint32_t big_endian_u16(const uint8_t* p) { return uint32_t(p[0]) << 8 | p[1]; }
uint32_t big_endian_u32(const uint8_t* p) { return uint32_t(p[0]) << 24 | uint32_t(p[1]) << 16 | uint32_t(p[2]) << 8 | p[3]; }

bool is_start_of_frame(uint8_t marker) {
  return marker >= 0xC0 && marker <= 0xCF && marker != 0xC4 && marker != 0xC8 && marker != 0xCC;
}

cv::Mat wrap(std::span<const uint8_t> bytes) {
  // imdecode only reads its input; the cast is for cv::Mat's constructor.
  return cv::Mat(1, int(bytes.size()), CV_8UC1, const_cast<uint8_t*>(bytes.data()));
}

cv::Mat decode_or_empty(std::span<const uint8_t> bytes, int flags) {
  try {
    return cv::imdecode(wrap(bytes), flags);
  } catch (const cv::Exception&) {
    return {};
  }
}

}  // namespace

std::optional<ImageSize> jpeg_size(std::span<const uint8_t> bytes, std::string* error) {
  const size_t n = bytes.size();
  if (n < 4 || bytes[0] != 0xFF || bytes[1] != 0xD8) {
    *error = "JPEG does not start with the SOI marker";
    return std::nullopt;
  }
  if (bytes[n - 2] != 0xFF || bytes[n - 1] != 0xD9) {
    *error = "JPEG does not end with the EOI marker (truncated?)";
    return std::nullopt;
  }
  size_t at = 2;
  while (at + 4 <= n) {
    if (bytes[at] != 0xFF) {
      *error = "JPEG marker expected at byte " + std::to_string(at);
      return std::nullopt;
    }
    const uint8_t marker = bytes[at + 1];
    if (marker == 0xFF) {  // fill byte
      ++at;
      continue;
    }
    if (marker == 0x01 || (marker >= 0xD0 && marker <= 0xD8)) {  // markers without a length
      at += 2;
      continue;
    }
    if (marker == 0xD9 || marker == 0xDA) break;  // EOI or scan data before any frame header
    const uint32_t length = big_endian_u16(&bytes[at + 2]);
    if (length < 2 || at + 2 + length > n) {
      *error = "JPEG segment at byte " + std::to_string(at) + " runs past the end";
      return std::nullopt;
    }
    if (is_start_of_frame(marker)) {
      if (length < 8) {
        *error = "JPEG frame header too short";
        return std::nullopt;
      }
      const uint8_t* sof = &bytes[at + 4];
      return ImageSize{big_endian_u16(sof + 3), big_endian_u16(sof + 1), sof[5], sof[0]};
    }
    at += 2 + length;
  }
  *error = "JPEG has no frame header (SOFn)";
  return std::nullopt;
}

std::optional<ImageSize> png_size(std::span<const uint8_t> bytes, std::string* error) {
  static const uint8_t signature[8] = {0x89, 'P', 'N', 'G', 0x0D, 0x0A, 0x1A, 0x0A};
  if (bytes.size() < 33 || std::memcmp(bytes.data(), signature, 8) != 0) {
    *error = "not a PNG (signature missing or file shorter than its header)";
    return std::nullopt;
  }
  if (big_endian_u32(&bytes[8]) != 13 || std::memcmp(&bytes[12], "IHDR", 4) != 0) {
    *error = "PNG does not start with an IHDR chunk";
    return std::nullopt;
  }
  const uint8_t color_type = bytes[25];
  // A palette image (type 3) or an invalid type counts as 0 channels: never what a plane expects.
  const uint32_t channels = color_type == 0 ? 1 : color_type == 2 ? 3 : color_type == 4 ? 2 : color_type == 6 ? 4 : 0;
  return ImageSize{big_endian_u32(&bytes[16]), big_endian_u32(&bytes[20]), channels, bytes[24]};
}

std::vector<uint8_t> encode_color_jpeg(const HostImage& rgba, int quality) {
  if (rgba.format != PixelFormat::RGBA32F) throw std::invalid_argument("portrait color must be RGBA32F");
  cv::Mat bgr(int(rgba.height), int(rgba.width), CV_8UC3);
  for (uint32_t y = 0; y < rgba.height; ++y) {
    auto* row = bgr.ptr<uint8_t>(int(y));
    const float* texel = &rgba.texels[rgba.index(0, y)];
    for (uint32_t x = 0; x < rgba.width; ++x, texel += 4)
      for (int c = 0; c < 3; ++c)  // NaN goes to 0: fmax picks the number
        row[3 * x + (2 - c)] = uint8_t(std::fmin(std::fmax(texel[c], 0.0f), 1.0f) * 255.0f + 0.5f);
  }
  std::vector<uint8_t> out;
  if (!cv::imencode(".jpg", bgr, out, {cv::IMWRITE_JPEG_QUALITY, std::clamp(quality, 1, 100)}))
    throw std::runtime_error("OpenCV could not encode the portrait color as JPEG");
  return out;
}

std::optional<std::string> decode_color_jpeg(std::span<const uint8_t> bytes, HostImage& rgba) {
  std::string error;
  const auto size = jpeg_size(bytes, &error);
  if (!size) return error;
  if (size->width != rgba.width || size->height != rgba.height)
    return "color JPEG is " + std::to_string(size->width) + "x" + std::to_string(size->height) + ", declared " +
           std::to_string(rgba.width) + "x" + std::to_string(rgba.height);
  if (size->channels != 3) return "color JPEG has " + std::to_string(size->channels) + " components, expected 3";
  const cv::Mat bgr = decode_or_empty(bytes, cv::IMREAD_COLOR | cv::IMREAD_IGNORE_ORIENTATION);
  if (bgr.empty()) return std::string("color JPEG does not decode");
  if (bgr.type() != CV_8UC3 || uint32_t(bgr.cols) != rgba.width || uint32_t(bgr.rows) != rgba.height)
    return std::string("color JPEG decodes to a different size or type than declared");
  for (uint32_t y = 0; y < rgba.height; ++y) {
    const auto* row = bgr.ptr<uint8_t>(int(y));
    float* texel = &rgba.texels[rgba.index(0, y)];
    for (uint32_t x = 0; x < rgba.width; ++x, texel += 4)
      for (int c = 0; c < 3; ++c) texel[c] = float(row[3 * x + (2 - c)]) / 255.0f;
  }
  return std::nullopt;
}

std::vector<uint8_t> encode_float_plane_png(const HostImage& image, uint32_t channel, int compression) {
  if (channel >= image.channels()) throw std::invalid_argument("float plane: no such channel");
  const int w = int(image.width), h = int(image.height);
  const uint32_t stride = image.channels();
  cv::Mat planes(4 * h, w, CV_8UC1);
  for (int y = 0; y < h; ++y) {
    const float* texel = image.texels.data() + size_t(y) * size_t(w) * stride + channel;
    uint8_t* rows[4] = {planes.ptr<uint8_t>(y), planes.ptr<uint8_t>(h + y), planes.ptr<uint8_t>(2 * h + y),
                        planes.ptr<uint8_t>(3 * h + y)};
    for (int x = 0; x < w; ++x, texel += stride) {
      const uint32_t bits = std::bit_cast<uint32_t>(*texel);
      for (int p = 0; p < 4; ++p) rows[p][x] = uint8_t(bits >> (8 * (3 - p)));
    }
  }
  std::vector<uint8_t> out;
  // Run-length strategy: on these planes (long runs of one byte around the person) it is both the
  // smallest and as fast as the default (`remotetouch bench net` compares them).
  if (!cv::imencode(".png", planes, out,
                    {cv::IMWRITE_PNG_COMPRESSION, std::clamp(compression, 0, 9), cv::IMWRITE_PNG_STRATEGY,
                     cv::IMWRITE_PNG_STRATEGY_RLE}))
    throw std::runtime_error("OpenCV could not encode a float plane as PNG");
  return out;
}

std::optional<std::string> decode_float_plane_png(std::span<const uint8_t> bytes, HostImage& image, uint32_t channel) {
  std::string error;
  const auto size = png_size(bytes, &error);
  if (!size) return error;
  if (size->width != image.width || uint64_t(size->height) != 4ull * image.height)
    return "PNG is " + std::to_string(size->width) + "x" + std::to_string(size->height) + ", expected " +
           std::to_string(image.width) + "x" + std::to_string(4ull * image.height) + " (four byte planes)";
  if (size->channels != 1 || size->bit_depth != 8) return std::string("PNG is not 8-bit grey");
  const cv::Mat planes = decode_or_empty(bytes, cv::IMREAD_UNCHANGED);
  if (planes.empty()) return std::string("PNG does not decode (corrupt or truncated)");
  if (planes.type() != CV_8UC1 || uint32_t(planes.cols) != image.width || uint32_t(planes.rows) != 4 * image.height)
    return std::string("PNG decodes to a different size or type than declared");
  const int w = int(image.width), h = int(image.height);
  const uint32_t stride = image.channels();
  for (int y = 0; y < h; ++y) {
    float* texel = image.texels.data() + size_t(y) * size_t(w) * stride + channel;
    const uint8_t* rows[4] = {planes.ptr<uint8_t>(y), planes.ptr<uint8_t>(h + y), planes.ptr<uint8_t>(2 * h + y),
                              planes.ptr<uint8_t>(3 * h + y)};
    for (int x = 0; x < w; ++x, texel += stride) {
      uint32_t bits = 0;
      for (int p = 0; p < 4; ++p) bits |= uint32_t(rows[p][x]) << (8 * (3 - p));
      *texel = std::bit_cast<float>(bits);
    }
  }
  return std::nullopt;
}

}  // namespace rt::net
