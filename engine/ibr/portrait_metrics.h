#pragma once
// How close a rendered portrait is to the simulator's ground truth of the same target view
// (`remotetouch eval ibr`). Accumulates over frames: PSNRs come from the total squared error,
// the depth error from all edge pixels, the IoU from summed intersections and unions.
#include <cstddef>
#include <nlohmann/json.hpp>

#include "image/host_image.h"

namespace rt::ibr {

struct MetricRegions {
  int hand_dilation_px = 4;  // the hand mask grown by this many pixels (edges count)
  int edge_band_px = 3;      // pixels this close to a depth edge of the truth
  float depth_edge_m = 0.05f;  // a jump this large between neighbours is a depth edge
};

struct PortraitError {
  HostImage color_error;  // r32f: mean absolute RGB error of (premultiplied) portrait vs truth
  HostImage depth_error_mm;  // r32f: |depth - truth| where both are set, else 0
  double psnr_fg_db = 0;     // this frame's own (NaN without foreground)
};

// Where the foreground's squared error lies (each truth-foreground pixel in the first that
// applies): pixels the portrait leaves uncovered (alpha < 0.5), the band around the person's
// outline, the band around depth jumps inside it (hand over body), and the rest.
enum class ErrorRegion { Uncovered, Outline, DepthEdge, Interior };
inline constexpr const char* kErrorRegionNames[] = {"uncovered", "outline", "depth_edge", "interior"};
inline constexpr size_t kErrorRegionCount = 4;

class PortraitMetrics {
 public:
  explicit PortraitMetrics(MetricRegions regions = {}) : regions_(regions) {}

  // portrait rgba32f (straight alpha), depth r32f metres; truth: color rgba8 premultiplied by
  // its coverage (the simulator box-filters the person over a zero background, so an edge pixel
  // half covered is half its color with alpha 0.5), depth r32f metres (0 = nothing), part r32f
  // (RT_PART_HAND marks the hand). Both are compared over black.
  // Returns this frame's error images.
  PortraitError add(const HostImage& portrait, const HostImage& depth, const HostImage& truth_color,
                    const HostImage& truth_depth, const HostImage& truth_part);

  double psnr_fg_db() const;
  double psnr_hand_db() const;   // NaN without hand pixels
  double depth_mae_edge_mm() const;
  double alpha_iou() const;
  double depth_bias_mm() const;  // mean signed error (portrait - truth) where both are set
  // The region's share of the foreground's pixels and of its squared error, and its own PSNR.
  double region_pixel_share(ErrorRegion region) const;
  double region_error_share(ErrorRegion region) const;
  double region_psnr_db(ErrorRegion region) const;
  nlohmann::json to_json() const;

 private:
  MetricRegions regions_;
  double fg_squared_error_ = 0, hand_squared_error_ = 0, edge_abs_error_mm_ = 0;
  double signed_error_mm_ = 0;
  size_t depth_pixels_ = 0;
  size_t fg_values_ = 0, hand_values_ = 0, edge_pixels_ = 0, intersection_ = 0, union_ = 0;
  size_t frames_ = 0;
  double region_squared_error_[kErrorRegionCount] = {};
  size_t region_pixels_[kErrorRegionCount] = {};
};

}  // namespace rt::ibr
