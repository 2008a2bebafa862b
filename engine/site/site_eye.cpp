#include "site/site_eye.h"

#include <opencv2/core.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>

#include "session/latency_stats.h"
#include "viewer/eye_detector.h"
#include "viewer/eye_depth.h"

namespace rt::site {
namespace {

// The detector wants 8-bit BGR; HostImage holds [0, 1] floats.
cv::Mat bgr8(const HostImage& image) {
  if (image.channels() < 3) return {};
  cv::Mat bgr(int(image.height), int(image.width), CV_8UC3);
  for (uint32_t y = 0; y < image.height; ++y) {
    auto* row = bgr.ptr<cv::Vec3b>(int(y));
    for (uint32_t x = 0; x < image.width; ++x)
      for (uint32_t c = 0; c < 3; ++c)
        row[x][2 - c] = uint8_t(std::lround(std::clamp(image.at(x, y, c), 0.0f, 1.0f) * 255.0f));
  }
  return bgr;
}

}  // namespace

EyeSearch::EyeSearch(const EyeSearchOptions& options) : options_(options), estimator_(options.viewpoint) {
  if (options_.max_frames < options_.viewpoint.frames_needed)
    throw std::invalid_argument("eye search: max_frames (" + std::to_string(options_.max_frames) +
                                ") must be at least the frames the estimate needs (" +
                                std::to_string(options_.viewpoint.frames_needed) + ")");
  if (!options_.use_seat_because.empty()) give_up(options_.use_seat_because);
}

EyeSearch::State EyeSearch::add(uint64_t timestamp_us, const EyePair& frame) {
  if (state_ != State::Searching) return state_;
  ++frames_;
  estimator_.add(timestamp_us, frame);
  if (frame.ok()) {
    ++frames_with_eyes_;
  } else {
    last_miss_ = frame.message.empty() ? failure_name(frame.failure) : frame.message;
  }
  const InitialViewpoint result = estimator_.result();
  if (result.ok()) {
    state_ = State::Found;
    eye_ = result.midpoint;
    spread_m_ = result.spread_m;
  } else if (frames_ >= options_.max_frames) {
    state_ = State::GaveUp;
    reason_ = frames_with_eyes_ == 0
                  ? "no face found in " + std::to_string(frames_) + " frames: " + last_miss_
                  : "no steady viewpoint in " + std::to_string(frames_) + " frames: " + result.message;
  }
  return state_;
}

void EyeSearch::give_up(const std::string& reason) {
  if (state_ != State::Searching) return;
  state_ = State::GaveUp;
  reason_ = reason;
}

std::string EyeSearch::source() const {
  switch (state_) {
    case State::Found: {
      char spread[32];
      std::snprintf(spread, sizeof spread, "%.1f", spread_m_ * 1000.0);
      return "cameras (" + std::to_string(frames_) + " frames, spread " + spread + " mm)";
    }
    case State::GaveUp: return "seat (" + reason_ + ")";
    case State::Searching: break;
  }
  return "seat (searching for the eyes: " + std::to_string(frames_) + " of at most " + std::to_string(options_.max_frames) +
         " frames examined)";
}

ViewerEyeFinder::ViewerEyeFinder(std::vector<Camera> cameras, const Eigen::Vector3d& seat_eye,
                                 const EyeSearchOptions& options, std::function<void(const std::string&)> on_decided,
                                 std::vector<Camera> depth_cameras)
    : cameras_(std::move(cameras)), depth_cameras_(std::move(depth_cameras)), seat_eye_(seat_eye), on_decided_(std::move(on_decided)), search_(options) {
  thread_ = std::thread([this] { run(); });
}

ViewerEyeFinder::~ViewerEyeFinder() {
  frames_.close();
  thread_.join();
}

bool ViewerEyeFinder::wants_frame() const {
  std::lock_guard lock(mutex_);
  return search_.state() == EyeSearch::State::Searching && !busy_;
}

void ViewerEyeFinder::offer(uint64_t timestamp_us, const std::vector<sim::RgbdImage>& images) {
  Offered offered{timestamp_us, {}, {}};
  for (const sim::RgbdImage& image : images) {
    offered.color.push_back(image.color);
    if (!depth_cameras_.empty()) offered.depth_mm.push_back(image.depth_mm);
  }
  {
    std::lock_guard lock(mutex_);
    if (search_.state() != EyeSearch::State::Searching) return;
    busy_ = true;
  }
  frames_.put(std::move(offered));
}

Eigen::Vector3d ViewerEyeFinder::eye() const {
  std::lock_guard lock(mutex_);
  return search_.eye_or(seat_eye_);
}

std::string ViewerEyeFinder::source() const {
  std::lock_guard lock(mutex_);
  return search_.source();
}

bool ViewerEyeFinder::decided() const {
  std::lock_guard lock(mutex_);
  return search_.state() != EyeSearch::State::Searching;
}

nlohmann::json ViewerEyeFinder::to_json() const {
  std::lock_guard lock(mutex_);
  const Eigen::Vector3d eye = search_.eye_or(seat_eye_);
  const size_t frames = search_.frames(), with_eyes = search_.frames_with_eyes();
  return {{"source", search_.state() == EyeSearch::State::Found ? "cameras" : "seat"},
          {"describe", search_.source()},
          {"position_m", {eye.x(), eye.y(), eye.z()}},
          {"frames_examined", frames},
          {"frames_with_eyes", with_eyes},
          {"fraction_with_eyes", frames ? nlohmann::json(double(with_eyes) / double(frames)) : nlohmann::json()}};
}

void ViewerEyeFinder::run() {
  auto decide = [&](auto&& change) {
    std::string source;
    {
      std::lock_guard lock(mutex_);
      change();
      busy_ = false;
      if (search_.state() == EyeSearch::State::Searching) return;
      source = search_.source();
    }
    if (on_decided_) on_decided_(source);
  };
  if (decided()) {  // told to use the seat: no detector, no frames
    if (on_decided_) on_decided_(source());
    return;
  }
  std::unique_ptr<EyeDetector> detector;
  try {
    detector = std::make_unique<EyeDetector>();
  } catch (const std::exception& error) {
    decide([&] { search_.give_up(std::string("the eye detector cannot start: ") + error.what()); });
    return;
  }
  while (true) {
    std::optional<Offered> offered = frames_.wait_take(std::chrono::milliseconds(100));
    if (!offered) {
      if (frames_.closed()) return;
      continue;
    }
    if (offered->color.size() != cameras_.size()) {
      decide([&] {
        search_.give_up("the frames have " + std::to_string(offered->color.size()) + " cameras, the site " +
                        std::to_string(cameras_.size()));
      });
      return;
    }
    std::vector<cv::Mat> images;
    for (size_t k = 0; k < cameras_.size(); ++k) {
      const HostImage& color = offered->color[k];
      // A camera whose image is not the calibrated size does not take part.
      const bool fits = color.width == cameras_[k].intrinsics.width && color.height == cameras_[k].intrinsics.height;
      images.push_back(fits ? bgr8(color) : cv::Mat());
    }
    const EyePair pair = locate_viewer_eyes_rgbd(*detector, cameras_, images, depth_cameras_, offered->depth_mm);
    decide([&] { search_.add(offered->timestamp_us, pair); });
    if (decided()) return;
  }
}

void EyeErrorStats::add(const Eigen::Vector3d& used, const Eigen::Vector3d& truth) {
  std::lock_guard lock(mutex_);
  errors_mm_.push_back((used - truth).norm() * 1000.0);
  offset_sum_mm_ += (used - truth) * 1000.0;
}

nlohmann::json EyeErrorStats::to_json() const {
  std::lock_guard lock(mutex_);
  if (errors_mm_.empty())
    return {{"frames", 0}, {"first_frame_mm", nullptr}, {"median_mm", nullptr}, {"p95_mm", nullptr}, {"max_mm", nullptr}, {"mean_offset_mm", nullptr}};
  const Eigen::Vector3d mean = offset_sum_mm_ / double(errors_mm_.size());
  return {{"frames", errors_mm_.size()},
          {"first_frame_mm", errors_mm_.front()},
          {"median_mm", session::percentile(errors_mm_, 0.5)},
          {"p95_mm", session::percentile(errors_mm_, 0.95)},
          {"max_mm", *std::max_element(errors_mm_.begin(), errors_mm_.end())},
          {"mean_offset_mm", {mean.x(), mean.y(), mean.z()}}};
}

}  // namespace rt::site
