#include "media/depth_alpha_codec.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace rt::media {

std::string check_depth_range(const DepthRange& range) {
  if (!std::isfinite(range.near_m) || !std::isfinite(range.far_m)) return "the depth range is not finite";
  if (range.near_m <= 0.0) return "the depth range's near end must be above 0 m";
  if (range.far_m <= range.near_m) return "the depth range's far end must be beyond its near end";
  return {};
}

uint16_t encode_depth_alpha(float depth_m, float alpha, const DepthRange& range) {
  if (!(alpha >= 0.5f)) return kEmptyCode;  // NaN alpha is empty too
  double d = std::isfinite(depth_m) && depth_m > 0.0f ? double(depth_m) : range.near_m;
  d = std::clamp(d, range.near_m, range.far_m);
  const double code = double(kDepthCodeMin) + (d - range.near_m) / range.step_m();
  return uint16_t(std::clamp(std::lround(code), long(kDepthCodeMin), long(kDepthCodeMax)));
}

void decode_depth_alpha(uint16_t code, const DepthRange& range, float& depth_m, float& alpha) {
  if (code < kAlphaThreshold) {
    depth_m = 0.0f;
    alpha = 0.0f;
    return;
  }
  // Codes between the threshold and the first depth code are ringing at the silhouette's edge:
  // the user, at the near end of the range's first code.
  const int c = std::clamp(int(code), int(kDepthCodeMin), int(kDepthCodeMax));
  depth_m = float(range.near_m + double(c - kDepthCodeMin) * range.step_m());
  alpha = 1.0f;
}

uint16_t encode_alpha(float alpha) {
  if (!(alpha > 0.0f)) return 0;  // NaN too: empty, as the luma codes it
  const double off_hard = alpha >= 0.5f ? 1.0 - double(std::min(alpha, 1.0f)) : double(alpha);
  return uint16_t(std::lround(off_hard * 2.0 * kAlphaCodeMax));
}

float decode_alpha(uint16_t luma_code, uint16_t alpha_code) {
  const int code = std::min<int>(alpha_code, kAlphaCodeMax);
  const float off_hard = code <= kAlphaSnapCodes ? 0.0f : float(code) / float(2 * kAlphaCodeMax);
  if (luma_code >= kAlphaThreshold) return 1.0f - off_hard;
  // Below the luma's threshold of 0.5 whatever the codec made of the matte.
  return std::min(std::nextafter(0.5f, 0.0f), off_hard);
}

namespace {
void check_plane_images(const HostImage& color, const HostImage& depth) {
  if (color.format != PixelFormat::RGBA32F || depth.format != PixelFormat::R32F || color.width != depth.width ||
      color.height != depth.height)
    throw std::invalid_argument("depth/alpha plane: colour must be RGBA32F and depth R32F of the same size");
}
void check_plane_span(size_t size, size_t stride, uint32_t width, uint32_t height) {
  if (stride < width || (height > 0 && size < stride * (height - 1) + width))
    throw std::invalid_argument("depth/alpha plane: the luma or alpha plane is smaller than the image");
}
}  // namespace

void encode_depth_alpha_plane(const HostImage& color, const HostImage& depth, const DepthRange& range,
                              std::span<uint16_t> luma, std::span<uint16_t> alpha, size_t stride) {
  check_plane_images(color, depth);
  check_plane_span(luma.size(), stride, depth.width, depth.height);
  check_plane_span(alpha.size(), stride, depth.width, depth.height);
  for (uint32_t y = 0; y < depth.height; ++y)
    for (uint32_t x = 0; x < depth.width; ++x) {
      const float a = color.at(x, y, 3);
      luma[y * stride + x] = encode_depth_alpha(depth.at(x, y), a, range);
      alpha[y * stride + x] = encode_alpha(a);
    }
}

void decode_depth_alpha_plane(std::span<const uint16_t> luma, std::span<const uint16_t> alpha, size_t stride,
                              const DepthRange& range, HostImage& color, HostImage& depth) {
  check_plane_images(color, depth);
  check_plane_span(luma.size(), stride, depth.width, depth.height);
  check_plane_span(alpha.size(), stride, depth.width, depth.height);
  const uint32_t w = depth.width, h = depth.height;
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x) {
      float d = 0.0f, hard = 0.0f;
      decode_depth_alpha(luma[y * stride + x], range, d, hard);
      depth.at(x, y) = d;
      color.at(x, y, 3) = decode_alpha(luma[y * stride + x], alpha[y * stride + x]);
    }
  // A soft pixel outside the silhouette is the user's edge only beside the user: it takes the
  // nearest user neighbour's depth (the edge belongs to the surface in front). Read from the luma,
  // so the order of the pixels does not matter.
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x) {
      if (luma[y * stride + x] >= kAlphaThreshold || color.at(x, y, 3) == 0.0f) continue;
      float nearest = 0.0f;
      for (uint32_t ny = y ? y - 1 : 0; ny <= std::min(y + 1, h - 1); ++ny)
        for (uint32_t nx = x ? x - 1 : 0; nx <= std::min(x + 1, w - 1); ++nx) {
          if (luma[ny * stride + nx] < kAlphaThreshold) continue;
          const float d = depth.at(nx, ny);
          if (nearest == 0.0f || d < nearest) nearest = d;
        }
      depth.at(x, y) = nearest;
      if (nearest == 0.0f) color.at(x, y, 3) = 0.0f;
    }
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x)
      if (color.at(x, y, 3) == 0.0f)
        for (uint32_t c = 0; c < 3; ++c) color.at(x, y, c) = 0.0f;
}

}  // namespace rt::media
