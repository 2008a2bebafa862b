#include "hand/appearance_adaption.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace rt::hand {
namespace {

nlohmann::json optional_json(const std::optional<uint64_t>& value) { return value ? nlohmann::json(*value) : nlohmann::json(); }

nlohmann::json statistics_json(const LabStatistics& s) { return {{"mean", s.mean}, {"sigma", s.sigma}}; }

LabStatistics statistics(const std::array<float, 4>& mean, const std::array<float, 4>& sigma) {
  LabStatistics s;
  for (int c = 0; c < 3; ++c) s.mean[size_t(c)] = mean[size_t(c)], s.sigma[size_t(c)] = sigma[size_t(c)];
  return s;
}

}  // namespace

const char* appearance_phase_name(AppearancePhase phase) {
  switch (phase) {
    case AppearancePhase::Waiting: return "waiting";
    case AppearancePhase::Fitted: return "fitted";
    case AppearancePhase::Stale: return "stale";
  }
  return "?";
}

const char* adaption_outcome_name(AdaptionOutcome outcome) {
  switch (outcome) {
    case AdaptionOutcome::Fitted: return "fitted";
    case AdaptionOutcome::RegionTooSmall: return "region_too_small";
    case AdaptionOutcome::NotFinite: return "not_finite";
  }
  return "?";
}

double appearance_weight(double fitted_before, double smoothing) {
  return std::max(1.0 / (std::max(fitted_before, 0.0) + 1.0), std::clamp(smoothing, 0.0, 1.0));
}

std::string AppearanceStatus::describe() const {
  std::ostringstream s;
  switch (phase) {
    case AppearancePhase::Waiting:
      s << "waiting: no frame with the hand seen by the cameras yet";
      if (frames_tried > 0)
        s << " (" << frames_tried << " tried: " << frames_region_too_small << " with the hand on fewer than "
          << min_region_pixels << " pixels where portrait and mesh agree, the last on " << last_region_pixels << "; "
          << frames_not_finite << " not finite)";
      break;
    case AppearancePhase::Fitted:
      s << "fitted from " << frames_fitted << " frame" << (frames_fitted == 1 ? "" : "s");
      if (provisional)
        s << ", provisional: the hand was never seen beyond " << RT_FUSION_D_MAX_M
          << " m, only the part of it the cameras see closer";
      break;
    case AppearancePhase::Stale:
      s << "stale: last fitted " << frames_since_fit.value_or(0) << " frames ago (fitted from " << frames_fitted << " frame"
        << (frames_fitted == 1 ? "" : "s") << (provisional ? ", provisional" : "") << ")";
      break;
  }
  return s.str();
}

nlohmann::json AppearanceStatus::to_json() const {
  const bool known = phase != AppearancePhase::Waiting;
  return {{"state", appearance_phase_name(phase)},
          {"describe", describe()},
          {"provisional", provisional},
          {"frames_fitted", frames_fitted},
          {"frames_tried", frames_tried},
          {"frames_rejected", {{"region_too_small", frames_region_too_small}, {"not_finite", frames_not_finite}}},
          {"frames_displayed", frames_displayed},
          {"frames_since_fit", optional_json(frames_since_fit)},
          {"first_fit_display_frame", optional_json(first_fit_display_frame)},
          {"last_region_pixels", frames_tried ? nlohmann::json(last_region_pixels) : nlohmann::json()},
          {"min_region_pixels", min_region_pixels},
          {"stale_after_frames", stale_after_frames},
          {"image", known ? statistics_json(image) : nlohmann::json()},
          {"mesh", known ? statistics_json(mesh) : nlohmann::json()}};
}

AppearanceAdaption::AppearanceAdaption(uint64_t stale_after_frames, double min_region_pixels)
    : stale_after_frames_(stale_after_frames), min_region_pixels_(std::max(min_region_pixels, 1.0)) {}

AppearancePhase AppearanceAdaption::phase() const {
  if (!last_fit_at_) return AppearancePhase::Waiting;
  return displayed_ - *last_fit_at_ > stale_after_frames_ ? AppearancePhase::Stale : AppearancePhase::Fitted;
}

void AppearanceAdaption::frame_displayed(uint64_t count) {
  const AppearancePhase before = phase();
  displayed_ += count;
  note_phase_change(before);
}

void AppearanceAdaption::sync_frames_displayed(uint64_t total) {
  if (total > displayed_) frame_displayed(total - displayed_);
}

AdaptionOutcome AppearanceAdaption::record(const shader_abi::AppearanceState& before, const shader_abi::AppearanceState& after,
                                           bool hand_beyond_d_max) {
  const AppearancePhase phase_before = phase();
  ++tried_;
  state_ = after;
  // The reduce counts an update only when it used the frame (header.y); header.z is the frame's pixels.
  AdaptionOutcome outcome = AdaptionOutcome::Fitted;
  if (!(after.header[1] > before.header[1]))
    outcome = after.header[2] < min_region_pixels_ ? AdaptionOutcome::RegionTooSmall : AdaptionOutcome::NotFinite;
  if (outcome == AdaptionOutcome::Fitted) {
    if (!first_fit_at_) first_fit_at_ = displayed_;
    last_fit_at_ = displayed_;
    if (hand_beyond_d_max) fitted_beyond_d_max_ = true;
  } else {
    uint64_t& rejected = outcome == AdaptionOutcome::RegionTooSmall ? too_small_ : not_finite_;
    if (rejected++ == 0) push_event("rejected", adaption_outcome_name(outcome));
  }
  note_phase_change(phase_before);
  return outcome;
}

void AppearanceAdaption::reset() {
  state_ = {};
  tried_ = too_small_ = not_finite_ = 0;
  first_fit_at_.reset();
  last_fit_at_.reset();
  fitted_beyond_d_max_ = false;
}

AppearanceStatus AppearanceAdaption::status() const {
  AppearanceStatus s;
  s.phase = phase();
  s.provisional = provisional();
  s.frames_fitted = state_.header[0] > 0.5f ? uint64_t(std::llround(std::max(state_.header[1], 0.0f))) : 0;
  s.frames_tried = tried_;
  s.frames_region_too_small = too_small_;
  s.frames_not_finite = not_finite_;
  s.frames_displayed = displayed_;
  if (last_fit_at_) s.frames_since_fit = displayed_ - *last_fit_at_;
  s.first_fit_display_frame = first_fit_at_;
  s.last_region_pixels = state_.header[2];
  s.min_region_pixels = min_region_pixels_;
  s.stale_after_frames = stale_after_frames_;
  s.image = statistics(state_.image_mean, state_.image_sigma);
  s.mesh = statistics(state_.mesh_mean, state_.mesh_sigma);
  return s;
}

void AppearanceAdaption::note_phase_change(AppearancePhase before) {
  const AppearancePhase now = phase();
  if (now == before) return;
  if (now == AppearancePhase::Stale) push_event("stale");
  else if (now == AppearancePhase::Fitted) push_event(before == AppearancePhase::Waiting ? "fitted" : "refitted");
}

void AppearanceAdaption::push_event(const char* event, const char* reason) {
  nlohmann::json entry = status().to_json();
  entry["change"] = event;
  if (reason) entry["reason"] = reason;
  events_.push_back(std::move(entry));
}

std::vector<nlohmann::json> AppearanceAdaption::take_events() { return std::exchange(events_, {}); }

}  // namespace rt::hand
