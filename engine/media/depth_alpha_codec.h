#pragma once
// Depth and alpha of a portrait in one 10-bit luma plane, for a video codec (H.264 High10).
//
// Why one plane: the silhouette and the depth describe the same surface, so they share edges and
// motion; a second video track for alpha would cost another stream's bits and another pairing.
// Why a reserved code for "no user": alpha of the portrait is in practice a mask (soft only on a
// one-to-two-pixel edge) and depth is meaningless outside it. Empty pixels are coded as 0, depth
// codes start at kDepthCodeMin (128) and the decoder calls a pixel "user" when its code is at
// least kAlphaThreshold (64): the gap of 128 codes between "empty" and the nearest depth is far
// wider than the ringing a lossy codec puts on that step, so the silhouette survives where a
// depth value would be smeared into its neighbours. Soft alpha edges become hard (alpha >= 0.5 is
// the user); the colour track still carries the edge's pixels.
//
// Depth is quantized linearly over the portrait's working range [near, far] (metres of camera
// z) to the 896 codes 128..1023: 0.4..2.0 m gives 1.79 mm a code. Depth outside the range is
// clamped to it (the user of a seated call stays within it); depth 0 (no measurement) under
// alpha >= 0.5 is coded at `near` rather than as empty, so that the silhouette stays whole.
#include <cstdint>
#include <span>
#include <string>

#include "image/host_image.h"

namespace rt::media {

inline constexpr uint16_t kEmptyCode = 0;
inline constexpr uint16_t kAlphaThreshold = 64;
inline constexpr uint16_t kDepthCodeMin = 128;
inline constexpr uint16_t kDepthCodeMax = 1023;

struct DepthRange {
  double near_m = 0.4, far_m = 2.0;
  // Metres per code step.
  double step_m() const { return (far_m - near_m) / double(kDepthCodeMax - kDepthCodeMin); }
};

// Empty string when the range can be used, else why not (non-finite, near <= 0, far <= near).
std::string check_depth_range(const DepthRange& range);

uint16_t encode_depth_alpha(float depth_m, float alpha, const DepthRange& range);
// depth 0 and alpha 0 for codes below the threshold.
void decode_depth_alpha(uint16_t code, const DepthRange& range, float& depth_m, float& alpha);

// The whole plane: `luma` has width*height codes, row-major, rows `luma_stride` codes apart.
// `color` is the portrait's RGBA32F (its alpha is read), `depth` R32F, both width x height.
void encode_depth_alpha_plane(const HostImage& color, const HostImage& depth, const DepthRange& range,
                              std::span<uint16_t> luma, size_t luma_stride);
// Into depth (R32F) and the alpha channel of `color` (RGBA32F), both already width x height.
// Colour is set to 0 where the pixel is empty (straight alpha, as the direct session's portrait).
void decode_depth_alpha_plane(std::span<const uint16_t> luma, size_t luma_stride, const DepthRange& range,
                              HostImage& color, HostImage& depth);

}  // namespace rt::media
