#pragma once
// Depth and alpha of a portrait in one 10-bit 4:4:4 picture, for a video codec (H.264 High 4:4:4):
// the luma plane holds the silhouette and the depth, the first chroma plane the alpha matte's soft
// value, the second is constant.
//
// Why one picture: the silhouette and the depth describe the same surface, so they share edges and
// motion; a second video track for alpha would cost another stream's bits and another pairing.
// Why a reserved luma code for "no user": depth is meaningless outside the user. Empty pixels
// (alpha < 0.5) are coded as 0, depth codes start at kDepthCodeMin (128) and the decoder calls a
// pixel "user" when its code is at least kAlphaThreshold (64): the gap of 128 codes between "empty"
// and the nearest depth is far wider than the ringing a lossy codec puts on that step, so the
// silhouette survives where a depth value would be smeared into its neighbours.
// Why the alpha plane as well: the luma's silhouette is hard, and on a tiny portrait (the demo's,
// a hand a few pixels wide) its soft one-to-two-pixel edge is much of the hand: made
// hard, that edge cost more than everything else on the link together (tests/
// test_media_portrait_stages.cpp). The alpha plane codes how far alpha is from the luma's hard
// decision (1 - alpha on the user, alpha off it; 0..0.5 over the codes 0..511): zero but on the
// soft edge itself, so the codes spend their range on the half of alpha the luma leaves open (the
// plain matte, alpha over the codes, costs about as many bits for as much precision: the edge's
// motion is what costs, in either form). The decoder keeps the luma's decision (user or not) and
// takes the soft value within it, so codec noise on the matte can neither move the silhouette nor
// put alpha far from it: a soft pixel outside the luma's silhouette counts only next to it, and
// takes its depth from its nearest user neighbour.
//
// Depth is quantized linearly over the portrait's working range [near, far] (metres of camera
// z) to the 896 codes 128..1023: 0.4..2.0 m gives 1.79 mm a code. Depth outside the range is
// clamped to it (the user of a seated call stays within it); depth 0 (no measurement) under
// alpha >= 0.5 is coded at `near` rather than as empty, so that the silhouette stays whole.
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "image/host_image.h"

namespace rt::media {

inline constexpr uint16_t kEmptyCode = 0;
inline constexpr uint16_t kAlphaThreshold = 64;
inline constexpr uint16_t kDepthCodeMin = 128;
inline constexpr uint16_t kDepthCodeMax = 1023;
// The alpha plane: the distance of alpha from the luma's hard decision, 0..0.5 as 0..kAlphaCodeMax.
// A decoded code up to kAlphaSnapCodes is 0: the codec's noise on a flat matte, not a soft edge.
inline constexpr uint16_t kAlphaCodeMax = 511;
inline constexpr uint16_t kAlphaSnapCodes = 8;
// The largest portrait (in pixels) whose soft edge the alpha plane carries. The edge is a line of a
// pixel or two along the whole silhouette, moving with the user, so its bits grow with the
// portrait's side while its weight (edge pixels per user pixel) falls: one size up it more than
// doubled the depth track's rate and lost portraits of the call's test on a loaded machine, and at
// the largest it would take the track past its ceiling and the call past its budget
// (docs/webrtc.md has the figures).
// Beyond this size the plane is 0 (the edge hard, as the luma has it), which costs almost nothing.
inline constexpr size_t kSoftEdgeMaxPixels = 320 * 180;
// The second chroma plane's constant, the middle of 10 bits.
inline constexpr uint16_t kNeutralChromaCode = 512;

struct DepthRange {
  double near_m = 0.4, far_m = 2.0;
  // Metres per code step.
  double step_m() const { return (far_m - near_m) / double(kDepthCodeMax - kDepthCodeMin); }
};

// A decoded depth/alpha picture's two planes, each width*height codes, rows packed.
struct DepthAlphaCodes {
  std::vector<uint16_t> luma, alpha;
};

// Empty string when the range can be used, else why not (non-finite, near <= 0, far <= near).
std::string check_depth_range(const DepthRange& range);

// The luma code.
uint16_t encode_depth_alpha(float depth_m, float alpha, const DepthRange& range);
// From the luma code alone: depth 0 and alpha 0 below the threshold, else the depth and alpha 1.
void decode_depth_alpha(uint16_t code, const DepthRange& range, float& depth_m, float& alpha);
// The alpha plane's code (NaN is empty: 0).
uint16_t encode_alpha(float alpha);
// The soft alpha of a pixel from both its codes: within [0.5, 1] where the luma says user, within
// [0, 0.5) where it says empty; 1 or 0 where the alpha code is within the snap.
float decode_alpha(uint16_t luma_code, uint16_t alpha_code);

// The whole picture: `luma` and `alpha` have width*height codes each, row-major, rows `stride`
// codes apart. `color` is the portrait's RGBA32F (its alpha is read), `depth` R32F, both
// width x height.
void encode_depth_alpha_plane(const HostImage& color, const HostImage& depth, const DepthRange& range,
                              std::span<uint16_t> luma, std::span<uint16_t> alpha, size_t stride);
// Into depth (R32F) and the alpha channel of `color` (RGBA32F), both already width x height. A soft
// pixel outside the luma's silhouette is kept only beside a user pixel, at the nearest such
// neighbour's depth; colour is set to 0 where the pixel ends empty (straight alpha, as the direct
// session's portrait).
void decode_depth_alpha_plane(std::span<const uint16_t> luma, std::span<const uint16_t> alpha, size_t stride,
                              const DepthRange& range, HostImage& color, HostImage& depth);

}  // namespace rt::media
