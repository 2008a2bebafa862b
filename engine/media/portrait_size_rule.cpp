#include "media/portrait_size_rule.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <vector>

namespace rt::media {
namespace {
constexpr double kMaxUpWaitFactor = 8.0;
// The smallest picture the receiver scales up: the rule's smallest step is half the call's.
constexpr uint32_t kSmallestFraction = 4;
constexpr size_t kMinDecisions = 3;  // a median of fewer is one report's word

// The median loss of an even count is either middle one: `upper` picks the greater.
double median_loss(const std::deque<PortraitSizeRule::Decision>& decisions, bool upper);
}  // namespace

std::string check_portrait_size_rule(const PortraitSizeRuleOptions& o) {
  if (o.floor_kbps < 1) return "the portrait size rule needs the colour rate's floor (>= 1 kbit/s), not " + std::to_string(o.floor_kbps);
  if (!(o.near_floor >= 1 && o.near_floor < 10)) return "the portrait size rule's near-floor multiple must be in [1, 10)";
  if (!(o.loss_clear >= 0 && o.loss_clear < o.loss_pressed && o.loss_pressed < 1))
    return "the portrait size rule's losses must satisfy 0 <= clear < pressed < 1 (hysteresis between them)";
  if (!(o.round_trip_high_s > 0) || !std::isfinite(o.round_trip_high_s)) return "the portrait size rule's round trip must be positive";
  if (!(o.down_after_s > 0 && o.down_after_s < 600) || !(o.up_after_s > 0 && o.up_after_s < 600) ||
      !(o.flap_window_s >= 0 && o.flap_window_s < 3600))
    return "the portrait size rule's periods must be positive and under 600 s (its flap window under an hour)";
  return {};
}

std::pair<uint32_t, uint32_t> portrait_size_at_step(uint32_t width, uint32_t height, int step) {
  if (step < 0 || step > kPortraitSizeSteps)
    throw std::invalid_argument("a portrait size step between 0 and " + std::to_string(kPortraitSizeSteps) + ", not " +
                                std::to_string(step));
  static constexpr double kScale[kPortraitSizeSteps + 1] = {1.0, 0.75, 0.5};
  const auto even = [&](uint32_t side) {
    return std::max<uint32_t>(2, uint32_t(std::lround(double(side) * kScale[step] / 2.0)) * 2);
  };
  return {even(width), even(height)};
}

std::string check_received_picture_size(uint32_t width, uint32_t height, uint32_t call_width, uint32_t call_height) {
  if (width > call_width || height > call_height || width % 2 || height % 2 || width * kSmallestFraction < call_width ||
      height * kSmallestFraction < call_height)
    return "a decoded picture of " + std::to_string(width) + "x" + std::to_string(height) + ": the link carries " +
           std::to_string(call_width) + "x" + std::to_string(call_height) + " or an even size down to a quarter of it";
  return {};
}

std::vector<uint16_t> resample_codes_nearest(std::span<const uint16_t> codes, uint32_t from_width, uint32_t from_height,
                                             uint32_t to_width, uint32_t to_height) {
  if (from_width == 0 || from_height == 0 || to_width == 0 || to_height == 0 || codes.size() != size_t(from_width) * from_height)
    throw std::invalid_argument("resampling codes needs non-empty sizes and " + std::to_string(from_width) + "x" +
                                std::to_string(from_height) + " codes, got " + std::to_string(codes.size()));
  std::vector<uint16_t> out(size_t(to_width) * to_height);
  // Nearest by pixel centres (OpenCV's plain INTER_NEAREST rounds down, shifting the picture by up
  // to a pixel against the colour, which is scaled about the centres).
  cv::resize(cv::Mat(int(from_height), int(from_width), CV_16UC1, const_cast<uint16_t*>(codes.data())),
             cv::Mat(int(to_height), int(to_width), CV_16UC1, out.data()), cv::Size(int(to_width), int(to_height)), 0, 0,
             cv::INTER_NEAREST_EXACT);
  return out;
}

PortraitSizeRule::PortraitSizeRule(PortraitSizeRuleOptions options) : options_(options), up_after_s_(options.up_after_s) {
  if (const std::string why = check_portrait_size_rule(options_); !why.empty()) throw std::invalid_argument(why);
}

std::deque<PortraitSizeRule::Decision> PortraitSizeRule::period_of(double now_s, double period_s) const {
  std::deque<Decision> period;
  for (auto d = since_change_.rbegin(); d != since_change_.rend(); ++d) {
    period.push_front(*d);
    if (d->at_s <= now_s - period_s) return period.size() >= kMinDecisions ? period : std::deque<Decision>{};
  }
  return {};
}

int PortraitSizeRule::on_decision(double now_s, int color_kbps, double fraction_lost, double round_trip_s) {
  // A decision that says nothing usable is left out.
  if (!std::isfinite(now_s) || !std::isfinite(fraction_lost) || fraction_lost < 0 || fraction_lost > 1) return step_;
  const bool queueing = std::isfinite(round_trip_s) && round_trip_s > options_.round_trip_high_s;
  since_change_.push_back({now_s, queueing ? 1.0 : fraction_lost, color_kbps <= options_.floor_kbps * options_.near_floor});
  const double longest = std::max(options_.down_after_s, options_.up_after_s * kMaxUpWaitFactor);
  while (since_change_.size() > kMinDecisions && since_change_[1].at_s <= now_s - longest) since_change_.pop_front();

  const auto change = [&](int by) {
    step_ += by;
    (by < 0 ? steps_up_ : steps_down_)++;
    if (by > 0 && last_up_s_ >= 0 && now_s - last_up_s_ < options_.flap_window_s)
      up_after_s_ = std::min(up_after_s_ * 2, options_.up_after_s * kMaxUpWaitFactor);
    if (by < 0) last_up_s_ = now_s;
    last_change_s_ = now_s;
    since_change_.clear();  // the next change weighs only what came after this one
  };
  if (step_ < kPortraitSizeSteps) {
    const std::deque<Decision> period = period_of(now_s, options_.down_after_s);
    if (!period.empty() && std::all_of(period.begin(), period.end(), [](const Decision& d) { return d.at_floor; }) &&
        median_loss(period, false) > options_.loss_pressed) {
      change(+1);
      return step_;
    }
  }
  if (step_ > 0) {
    const std::deque<Decision> period = period_of(now_s, up_after_s_);
    if (!period.empty() && median_loss(period, true) <= options_.loss_clear) change(-1);
  } else if (last_change_s_ >= 0 && now_s - last_change_s_ >= options_.flap_window_s) {
    up_after_s_ = options_.up_after_s;  // at the call's size this long: the path has settled
  }
  return step_;
}

namespace {
double median_loss(const std::deque<PortraitSizeRule::Decision>& decisions, bool upper) {
  std::vector<double> losses;
  for (const auto& d : decisions) losses.push_back(d.loss);
  std::sort(losses.begin(), losses.end());
  return losses[upper ? losses.size() / 2 : (losses.size() - 1) / 2];
}
}  // namespace

}  // namespace rt::media
