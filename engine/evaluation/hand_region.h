#pragma once
// The region of the remote user's hand and forearm in a target view, from the simulator's
// ground truth: where the evaluation of the dual hand measures what the remote user sees.
#include "image/host_image.h"
#include "image/pixel_mask.h"

namespace rt::evaluation {

struct HandRegionSizes {
  int dilation_px = 3;     // the hand+forearm mask grown by this much: edges count
  int silhouette_px = 12;  // the neighbourhood in which silhouettes are compared
  float visible_tolerance_m = 0.002f;  // limb depth this close to the scene's: not hidden
};

struct HandRegion {
  uint32_t width = 0, height = 0;
  PixelMask hand_arm;    // the measured hand and forearm where visible
  PixelMask hand;        // its hand alone, fully covered pixels (colour differences)
  PixelMask region;      // hand_arm dilated: PSNR and SSIM
  PixelMask silhouette;  // hand_arm dilated further: silhouette IoU
  PixelMask user;        // the whole user
};

// scene_*: the truth of the whole scene (depth r32f metres, 0 = nothing; part r32f RT_PART_*;
// color rgba8 premultiplied by coverage). limb_*: the measured hand and forearm alone rendered
// in the same view (depth as above; part RT_PART_HAND on the hand, anything else > 0 on the
// forearm). A limb pixel counts where the scene's depth there is the limb's: nothing (the
// other hand, the body) lies in front of it. Throws std::invalid_argument on differing sizes.
HandRegion hand_region(const HostImage& scene_color, const HostImage& scene_depth, const HostImage& scene_part,
                       const HostImage& limb_depth, const HostImage& limb_part, const HandRegionSizes& sizes = {});

// The region as a site records it beside its ground truth (an R32F image, written as a grey
// PNG): 0 outside, 0.5 on the visible hand and forearm, 1 where that is a fully covered hand
// pixel. Decoding derives the dilated masks; `user` is then unknown and left empty.
HostImage encode_region(const HandRegion& region);
// Throws std::invalid_argument for an image that is not one channel.
HandRegion decode_region(const HostImage& encoded, const HandRegionSizes& sizes = {});

}  // namespace rt::evaluation
