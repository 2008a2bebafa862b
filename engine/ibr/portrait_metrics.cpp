#include "ibr/portrait_metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include "image/pixel_mask.h"
#include "shared/config.h"

namespace rt::ibr {
namespace {

double psnr(double squared_error, size_t values) {
  if (values == 0) return std::numeric_limits<double>::quiet_NaN();
  const double mse = squared_error / double(values);
  return mse > 0 ? 10.0 * std::log10(1.0 / mse) : 99.0;  // identical: a capped, finite figure
}

}  // namespace

PortraitError PortraitMetrics::add(const HostImage& portrait, const HostImage& depth, const HostImage& truth_color,
                                   const HostImage& truth_depth, const HostImage& truth_part) {
  const uint32_t w = portrait.width, h = portrait.height;
  for (const HostImage* image : {&depth, &truth_color, &truth_depth, &truth_part})
    if (image->width != w || image->height != h) throw std::invalid_argument("portrait metrics: images differ in size");
  const size_t n = size_t(w) * h;
  std::vector<uint8_t> foreground(n), hand(n), edge(n), outline(n);
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + x;
      foreground[i] = truth_part.at(x, y) > 0.5f;
      hand[i] = std::abs(truth_part.at(x, y) - float(RT_PART_HAND)) < 0.5f;
      // A depth edge: the person's outline, or a jump between neighbours (hand over body).
      const float z = truth_depth.at(x, y);
      for (auto [dx, dy] : {std::pair{1, 0}, std::pair{0, 1}}) {
        if (x + uint32_t(dx) >= w || y + uint32_t(dy) >= h) continue;
        const float other = truth_depth.at(x + uint32_t(dx), y + uint32_t(dy));
        const size_t j = size_t(y + uint32_t(dy)) * w + x + uint32_t(dx);
        if ((z > 0) != (other > 0)) outline[i] = outline[j] = 1;
        if ((z > 0) != (other > 0) || (z > 0 && std::abs(z - other) > regions_.depth_edge_m)) edge[i] = edge[j] = 1;
      }
    }
  hand = dilate_mask(hand, w, h, regions_.hand_dilation_px);
  edge = dilate_mask(edge, w, h, regions_.edge_band_px);
  outline = dilate_mask(outline, w, h, regions_.edge_band_px);

  PortraitError error{HostImage(w, h, PixelFormat::R32F), HostImage(w, h, PixelFormat::R32F)};
  double frame_squared_error = 0;
  size_t frame_values = 0;
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + x;
      const float alpha = std::clamp(portrait.at(x, y, 3), 0.0f, 1.0f);
      double squared = 0, absolute = 0;
      for (uint32_t c = 0; c < 3; ++c) {
        // Both over black: a missing portrait pixel costs its full color. The truth is over
        // black already (premultiplied); multiplying it by its alpha again would darken every
        // partly covered edge pixel a second time.
        const double difference = double(portrait.at(x, y, c)) * alpha - double(truth_color.at(x, y, c));
        squared += difference * difference;
        absolute += std::abs(difference);
      }
      error.color_error.at(x, y) = float(absolute / 3.0);
      if (foreground[i]) {
        fg_squared_error_ += squared, fg_values_ += 3;
        frame_squared_error += squared, frame_values += 3;
        const ErrorRegion region = alpha < 0.5f ? ErrorRegion::Uncovered
                                   : outline[i] ? ErrorRegion::Outline
                                   : edge[i]    ? ErrorRegion::DepthEdge
                                                : ErrorRegion::Interior;
        region_squared_error_[size_t(region)] += squared;
        ++region_pixels_[size_t(region)];
      }
      if (hand[i]) hand_squared_error_ += squared, hand_values_ += 3;
      const float z = depth.at(x, y), truth_z = truth_depth.at(x, y);
      if (z > 0 && truth_z > 0) {
        const double mm = std::abs(double(z) - truth_z) * 1000.0;
        error.depth_error_mm.at(x, y) = float(mm);
        signed_error_mm_ += (double(z) - truth_z) * 1000.0;
        ++depth_pixels_;
        if (edge[i]) edge_abs_error_mm_ += mm, ++edge_pixels_;
      }
      const bool covered = alpha > 0.5f;
      intersection_ += covered && foreground[i];
      union_ += covered || foreground[i];
    }
  ++frames_;
  error.psnr_fg_db = psnr(frame_squared_error, frame_values);
  return error;
}

double PortraitMetrics::psnr_fg_db() const { return psnr(fg_squared_error_, fg_values_); }
double PortraitMetrics::psnr_hand_db() const { return psnr(hand_squared_error_, hand_values_); }
double PortraitMetrics::depth_mae_edge_mm() const {
  return edge_pixels_ ? edge_abs_error_mm_ / double(edge_pixels_) : std::numeric_limits<double>::quiet_NaN();
}
double PortraitMetrics::depth_bias_mm() const {
  return depth_pixels_ ? signed_error_mm_ / double(depth_pixels_) : std::numeric_limits<double>::quiet_NaN();
}
double PortraitMetrics::alpha_iou() const {
  return union_ ? double(intersection_) / double(union_) : std::numeric_limits<double>::quiet_NaN();
}

double PortraitMetrics::region_pixel_share(ErrorRegion region) const {
  return fg_values_ ? double(region_pixels_[size_t(region)]) * 3.0 / double(fg_values_) : std::numeric_limits<double>::quiet_NaN();
}
double PortraitMetrics::region_error_share(ErrorRegion region) const {
  return fg_squared_error_ > 0 ? region_squared_error_[size_t(region)] / fg_squared_error_ : std::numeric_limits<double>::quiet_NaN();
}
double PortraitMetrics::region_psnr_db(ErrorRegion region) const {
  return psnr(region_squared_error_[size_t(region)], region_pixels_[size_t(region)] * 3);
}

nlohmann::json PortraitMetrics::to_json() const {
  auto number = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); };
  nlohmann::json regions;
  for (size_t r = 0; r < kErrorRegionCount; ++r) {
    const auto region = ErrorRegion(r);
    regions[kErrorRegionNames[r]] = {{"pixel_share", number(region_pixel_share(region))},
                                     {"error_share", number(region_error_share(region))},
                                     {"psnr_db", number(region_psnr_db(region))}};
  }
  return {{"fg_error_by_region", regions},
          {"psnr_fg_db", number(psnr_fg_db())},
          {"psnr_hand_db", number(psnr_hand_db())},
          {"depth_mae_edge_mm", number(depth_mae_edge_mm())},
          {"alpha_iou", number(alpha_iou())},
          {"depth_bias_mm", number(depth_bias_mm())},
          {"frames", frames_},
          {"foreground_values", fg_values_},
          {"hand_values", hand_values_},
          {"edge_pixels", edge_pixels_}};
}

}  // namespace rt::ibr
