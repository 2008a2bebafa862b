#include "media/portrait_quality.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

namespace rt::media {

PortraitQuality portrait_quality(const net::PortraitMessage& sent, const net::PortraitMessage& received) {
  const auto same = [](const HostImage& a, const HostImage& b) {
    return a.width == b.width && a.height == b.height && a.format == b.format;
  };
  if (!same(sent.color, received.color) || !same(sent.depth, received.depth) ||
      sent.color.format != PixelFormat::RGBA32F || sent.depth.format != PixelFormat::R32F ||
      sent.color.width != sent.depth.width || sent.color.height != sent.depth.height)
    throw std::invalid_argument("portrait quality: the sent and received portraits differ in size or format");
  PortraitQuality q;
  double squared = 0.0;
  size_t both = 0, either = 0, colour_samples = 0;
  std::vector<double> depth_errors;
  for (uint32_t y = 0; y < sent.depth.height; ++y)
    for (uint32_t x = 0; x < sent.depth.width; ++x) {
      for (uint32_t c = 0; c < 4; ++c)
        if (!std::isfinite(received.color.at(x, y, c))) q.all_finite = false;
      if (!std::isfinite(received.depth.at(x, y))) q.all_finite = false;
      const bool user_sent = sent.color.at(x, y, 3) >= 0.5f, user_received = received.color.at(x, y, 3) >= 0.5f;
      either += (user_sent || user_received) ? 1 : 0;
      if (!(user_sent && user_received)) continue;
      ++both;
      for (uint32_t c = 0; c < 3; ++c) {
        const double d = double(std::clamp(received.color.at(x, y, c), 0.0f, 1.0f)) -
                         double(std::clamp(sent.color.at(x, y, c), 0.0f, 1.0f));
        squared += d * d;
        ++colour_samples;
      }
      depth_errors.push_back(std::abs(double(received.depth.at(x, y)) - double(sent.depth.at(x, y))));
    }
  q.user_pixels = both;
  q.silhouette_iou = either == 0 ? 1.0 : double(both) / double(either);
  const double mse = colour_samples == 0 ? 0.0 : squared / double(colour_samples);
  q.psnr_user_db = mse <= 0.0 ? std::numeric_limits<double>::infinity() : 10.0 * std::log10(1.0 / mse);
  if (!depth_errors.empty()) {
    const auto at = [&](double fraction) {
      const size_t i = std::min(depth_errors.size() - 1, size_t(fraction * double(depth_errors.size())));
      std::nth_element(depth_errors.begin(), depth_errors.begin() + long(i), depth_errors.end());
      return depth_errors[i];
    };
    q.depth_median_error_m = at(0.5);
    q.depth_p90_error_m = at(0.9);
  }
  return q;
}

}  // namespace rt::media
