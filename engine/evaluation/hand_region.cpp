#include "evaluation/hand_region.h"

#include <cmath>
#include <stdexcept>

#include "shared/config.h"

namespace rt::evaluation {

HandRegion hand_region(const HostImage& scene_color, const HostImage& scene_depth, const HostImage& scene_part,
                       const HostImage& limb_depth, const HostImage& limb_part, const HandRegionSizes& sizes) {
  const uint32_t w = scene_depth.width, h = scene_depth.height;
  for (const HostImage* image : {&scene_color, &scene_part, &limb_depth, &limb_part})
    if (image->width != w || image->height != h) throw std::invalid_argument("hand region: the truth images differ in size");
  HandRegion out;
  out.width = w;
  out.height = h;
  const size_t n = size_t(w) * h;
  out.hand_arm.assign(n, 0);
  out.hand.assign(n, 0);
  out.user.assign(n, 0);
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + x;
      const float scene_z = scene_depth.at(x, y), limb_z = limb_depth.at(x, y);
      out.user[i] = scene_part.at(x, y) > 0.5f;
      // NaN compares false everywhere: a NaN depth is never part of the limb.
      const bool visible = limb_z > 0.0f && scene_z > 0.0f && std::abs(scene_z - limb_z) <= sizes.visible_tolerance_m;
      if (!visible) continue;
      out.hand_arm[i] = 1;
      const bool on_hand = std::abs(limb_part.at(x, y) - float(RT_PART_HAND)) < 0.5f;
      // Fully covered only: an edge pixel mixes the hand with what lies behind it.
      out.hand[i] = on_hand && scene_color.at(x, y, 3) >= 0.999f;
    }
  out.region = dilate_mask(out.hand_arm, w, h, sizes.dilation_px);
  out.silhouette = dilate_mask(out.hand_arm, w, h, sizes.silhouette_px);
  return out;
}

HostImage encode_region(const HandRegion& region) {
  HostImage out(region.width, region.height, PixelFormat::R32F);
  for (size_t i = 0; i < out.texels.size(); ++i) out.texels[i] = region.hand[i] ? 1.0f : region.hand_arm[i] ? 0.5f : 0.0f;
  return out;
}

HandRegion decode_region(const HostImage& encoded, const HandRegionSizes& sizes) {
  if (encoded.channels() != 1) throw std::invalid_argument("hand region: a recorded region has one channel");
  HandRegion out;
  out.width = encoded.width;
  out.height = encoded.height;
  const size_t n = size_t(encoded.width) * encoded.height;
  out.hand_arm.assign(n, 0);
  out.hand.assign(n, 0);
  for (size_t i = 0; i < n; ++i) {
    const float v = encoded.texels[i];  // NaN is neither
    out.hand_arm[i] = v > 0.25f;
    out.hand[i] = v > 0.75f;
  }
  out.region = dilate_mask(out.hand_arm, out.width, out.height, sizes.dilation_px);
  out.silhouette = dilate_mask(out.hand_arm, out.width, out.height, sizes.silhouette_px);
  out.user.assign(n, 0);
  return out;
}

}  // namespace rt::evaluation
