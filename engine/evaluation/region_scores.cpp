#include "evaluation/region_scores.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "hand/color_space.h"

namespace rt::evaluation {
namespace {

std::optional<double> psnr(double squared_error, size_t values) {
  if (values == 0) return std::nullopt;
  const double mse = squared_error / double(values);
  return mse > 0 ? 10.0 * std::log10(1.0 / mse) : 99.0;
}

std::optional<double> mean(double sum, size_t count) {
  if (count == 0) return std::nullopt;
  return sum / double(count);
}

double clamp01(float v) { return std::isfinite(v) ? std::clamp(double(v), 0.0, 1.0) : 1.0; }

// Linear RGB over black of a straight-alpha pixel (or of a premultiplied one, as it is);
// anything non-finite or out of range is clamped, so that a broken pixel is an error and not a
// NaN.
Eigen::Vector3d over_black(const HostImage& image, uint32_t x, uint32_t y, bool premultiplied) {
  const double alpha = premultiplied || image.channels() < 4 ? 1.0 : clamp01(image.at(x, y, 3));
  return Eigen::Vector3d(clamp01(image.at(x, y, 0)), clamp01(image.at(x, y, 1)), clamp01(image.at(x, y, 2))) * alpha;
}

double luminance(const Eigen::Vector3d& rgb) { return 0.2126 * rgb.x() + 0.7152 * rgb.y() + 0.0722 * rgb.z(); }

// The SSIM map of Wang et al. (2004): 11x11 Gaussian window of sigma 1.5, K1 0.01, K2 0.03, on
// values in [0, 1].
cv::Mat ssim_map(const cv::Mat& a, const cv::Mat& b) {
  const double c1 = 0.01 * 0.01, c2 = 0.03 * 0.03;
  auto blur = [](const cv::Mat& m) {
    cv::Mat out;
    cv::GaussianBlur(m, out, cv::Size(11, 11), 1.5, 1.5, cv::BORDER_REFLECT);
    return out;
  };
  const cv::Mat mu_a = blur(a), mu_b = blur(b);
  const cv::Mat mu_aa = mu_a.mul(mu_a), mu_bb = mu_b.mul(mu_b), mu_ab = mu_a.mul(mu_b);
  const cv::Mat var_a = blur(a.mul(a)) - mu_aa, var_b = blur(b.mul(b)) - mu_bb, cov = blur(a.mul(b)) - mu_ab;
  cv::Mat numerator = (2 * mu_ab + c1).mul(2 * cov + c2);
  cv::Mat denominator = (mu_aa + mu_bb + c1).mul(var_a + var_b + c2);
  cv::Mat map;
  cv::divide(numerator, denominator, map);
  return map;
}

}  // namespace

std::optional<double> FrameScore::psnr_db() const { return psnr(squared_error, values); }
std::optional<double> FrameScore::user_psnr_db() const { return psnr(user_squared_error, user_values); }
std::optional<double> FrameScore::ssim() const { return mean(ssim_sum, ssim_pixels); }
std::optional<double> FrameScore::delta_e() const { return mean(delta_e_sum, delta_e_pixels); }
std::optional<double> FrameScore::iou() const {
  if (union_pixels == 0) return std::nullopt;
  return double(intersection) / double(union_pixels);
}

FrameScore& FrameScore::operator+=(const FrameScore& o) {
  squared_error += o.squared_error;
  values += o.values;
  user_squared_error += o.user_squared_error;
  user_values += o.user_values;
  ssim_sum += o.ssim_sum;
  ssim_pixels += o.ssim_pixels;
  delta_e_sum += o.delta_e_sum;
  delta_e_pixels += o.delta_e_pixels;
  intersection += o.intersection;
  union_pixels += o.union_pixels;
  return *this;
}

FrameScore score_frame(const HostImage& shown, const HostImage& truth_color, const HandRegion& region) {
  const uint32_t w = region.width, h = region.height;
  if (shown.width != w || shown.height != h || truth_color.width != w || truth_color.height != h)
    throw std::invalid_argument("region scores: the shown image, the truth and the region differ in size");
  FrameScore score;
  cv::Mat shown_y(int(h), int(w), CV_64F), truth_y(int(h), int(w), CV_64F);
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + x;
      const Eigen::Vector3d a = over_black(shown, x, y, false), b = over_black(truth_color, x, y, true);
      shown_y.at<double>(int(y), int(x)) = luminance(a);
      truth_y.at<double>(int(y), int(x)) = luminance(b);
      const double squared = (a - b).squaredNorm();
      if (region.region[i]) score.squared_error += squared, score.values += 3;
      if (region.user[i]) score.user_squared_error += squared, score.user_values += 3;
      if (region.hand[i]) {
        score.delta_e_sum += hand::delta_e_2000(hand::rgb_to_cielab(a), hand::rgb_to_cielab(b));
        ++score.delta_e_pixels;
      }
      if (region.silhouette[i]) {
        const bool shown_in = std::isfinite(shown.at(x, y, 3)) && shown.at(x, y, 3) >= 0.5f;
        const bool truth_in = truth_color.at(x, y, 3) >= 0.5f;
        score.intersection += shown_in && truth_in;
        score.union_pixels += shown_in || truth_in;
      }
    }
  if (count_set(region.region) > 0) {
    const cv::Mat map = ssim_map(shown_y, truth_y);
    for (uint32_t y = 0; y < h; ++y)
      for (uint32_t x = 0; x < w; ++x)
        if (region.region[size_t(y) * w + x]) score.ssim_sum += map.at<double>(int(y), int(x)), ++score.ssim_pixels;
  }
  return score;
}

void ScoreTotals::add(const FrameScore& frame, std::optional<double> tip_error_px) {
  pooled_ += frame;
  ++frames_;
  if (tip_error_px && std::isfinite(*tip_error_px)) tip_sum_px_ += *tip_error_px, ++tip_frames_;
}

nlohmann::json ScoreTotals::to_json() const {
  nlohmann::json out = {{"frames", frames_}};
  auto put = [&](const char* key, std::optional<double> value) {
    if (value && std::isfinite(*value)) out[key] = *value;
  };
  put("psnr_hand_arm_db", pooled_.psnr_db());
  put("psnr_user_db", pooled_.user_psnr_db());
  put("ssim_hand_arm", pooled_.ssim());
  put("de_hand", pooled_.delta_e());
  put("iou_hand_arm", pooled_.iou());
  put("tip_err_px", mean(tip_sum_px_, tip_frames_));
  return out;
}

}  // namespace rt::evaluation
