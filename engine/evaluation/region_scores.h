#pragma once
// How close what the receiver shows is to the truth on the hand+forearm region (hand_region.h),
// one frame at a time and pooled over frames: PSNR from the summed squared error, SSIM and
// CIEDE2000 as means over the pooled pixels, the silhouette IoU from summed intersections and
// unions, the fingertip error as a mean over the frames that have one.
#include <cstddef>
#include <nlohmann/json.hpp>
#include <optional>

#include "evaluation/hand_region.h"

namespace rt::evaluation {

struct FrameScore {
  double squared_error = 0;  // over the region's pixels, RGB
  size_t values = 0;
  double user_squared_error = 0;  // over the whole user
  size_t user_values = 0;
  double ssim_sum = 0;  // SSIM of luminance, over the region's pixels
  size_t ssim_pixels = 0;
  double delta_e_sum = 0;  // CIEDE2000 over the hand's fully covered pixels
  size_t delta_e_pixels = 0;
  size_t intersection = 0, union_pixels = 0;  // silhouettes (alpha >= 0.5) in the silhouette region

  // Empty where the frame has no such pixels; PSNR is capped at 99 dB for identical images.
  std::optional<double> psnr_db() const;
  std::optional<double> user_psnr_db() const;
  std::optional<double> ssim() const;
  std::optional<double> delta_e() const;
  std::optional<double> iou() const;
  FrameScore& operator+=(const FrameScore& other);
};

// shown: rgba32f straight alpha (the receiver's fused image, before the background); truth:
// color rgba8 premultiplied by coverage. Both are compared premultiplied, that is over black.
// Non-finite shown values count as the worst error (1 per channel), never as NaN.
FrameScore score_frame(const HostImage& shown, const HostImage& truth_color, const HandRegion& region);

class ScoreTotals {
 public:
  void add(const FrameScore& frame, std::optional<double> tip_error_px);
  size_t frames() const { return frames_; }
  const FrameScore& pooled() const { return pooled_; }
  // psnr_hand_arm_db, psnr_user_db, ssim_hand_arm, de_hand, iou_hand_arm, tip_err_px, frames;
  // a figure without pixels is left out (never NaN).
  nlohmann::json to_json() const;

 private:
  FrameScore pooled_;
  size_t frames_ = 0;
  double tip_sum_px_ = 0;
  size_t tip_frames_ = 0;
};

}  // namespace rt::evaluation
