#pragma once
// Portrait images on the wire: color as JPEG (lossy, quality a parameter) and float planes (alpha,
// depth) losslessly as an 8-bit grey PNG of the float's bytes, one plane per byte, most
// significant first: the sign/exponent plane of a depth map is nearly constant and the mantissa
// planes are smooth, so deflate does well and the round trip is bit-exact. Before decoding, the
// image's own header is read and checked against the declared size, so a small malicious image
// cannot make the decoder allocate a huge one.
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "image/host_image.h"

namespace rt::net {

struct ImageSize {
  uint32_t width = 0, height = 0;
  uint32_t channels = 0;   // JPEG components; PNG: 1 grey, 3 RGB, ...
  uint32_t bit_depth = 8;  // PNG only
};

// Size and components from the SOFn marker of a JPEG; empty (with the reason) when it has none or
// does not start with SOI and end with EOI (a truncated JPEG decodes to grey without an error).
std::optional<ImageSize> jpeg_size(std::span<const uint8_t> bytes, std::string* error);
// Size, channels and bit depth from a PNG's IHDR.
std::optional<ImageSize> png_size(std::span<const uint8_t> bytes, std::string* error);

// RGB of an RGBA32F image (values clamped to [0, 1], rounded to 8 bits) as JPEG.
std::vector<uint8_t> encode_color_jpeg(const HostImage& rgba, int quality);
// Into channels 0..2 of `rgba` (width x height x RGBA32F, already allocated). Returns the error.
std::optional<std::string> decode_color_jpeg(std::span<const uint8_t> bytes, HostImage& rgba);

// One float channel of `image` as a lossless byte-plane PNG (width x 4*height, 8-bit grey).
std::vector<uint8_t> encode_float_plane_png(const HostImage& image, uint32_t channel, int compression);
// Into `channel` of `image` (already allocated at the declared size). Returns the error.
std::optional<std::string> decode_float_plane_png(std::span<const uint8_t> bytes, HostImage& image, uint32_t channel);

}  // namespace rt::net
