#pragma once
// How a portrait came through a lossy link, against the one that was sent: PSNR of the colour
// over the user's pixels, depth error over them, the silhouette's intersection over union, and
// whether anything decoded is NaN or infinite. The user is where the sent alpha is >= 0.5: the
// soft edge below that is what the depth/alpha track codes as empty by design.
#include "net/messages.h"

namespace rt::media {

struct PortraitQuality {
  double psnr_user_db = 0.0;          // RGB in [0, 1], over the pixels that are the user in both
  double depth_median_error_m = 0.0;  // |received - sent| over the pixels that are the user in both
  double depth_p90_error_m = 0.0;
  double silhouette_iou = 0.0;
  size_t user_pixels = 0;
  bool all_finite = true;
};

// Throws std::invalid_argument when the two portraits' images differ in size or format.
PortraitQuality portrait_quality(const net::PortraitMessage& sent, const net::PortraitMessage& received);

}  // namespace rt::media
