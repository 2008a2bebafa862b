#pragma once
// Appearance adaption's record (paper section 3.1.3, Eq. 3): whether the geometry hand's skin
// texture T' has been fitted to the remote user, from how many frames, and how long ago. The
// statistics live on the GPU (hand_color_reduce folds each frame into them); this reads the state
// the reduce left after each adaption frame and keeps what metrics.json and the events log say.
//
// Everything is counted in frames, never in seconds: the same frames give the same state and the
// same texture whether the receiver displays 1 frame/s (lavapipe) or 30. Owns no Vulkan objects.
//
//   waiting  no frame fitted yet (never enough pixels where portrait and mesh agree); the
//            template's own skin is drawn
//   fitted   from N frames; the latest within `stale_after_frames` displayed frames. Provisional
//            while every one of them had the hand inside d_max: a hand that reaches for the glass
//            fast is never tracked beyond it, and then the cameras' view of the arm (the depth test
//            keeps only what portrait and mesh agree on) is a better skin than the template's. The
//            first frame beyond d_max, where the cameras see the whole hand, starts the fit afresh,
//            and from then on frames inside d_max are not used
//   stale    fitted once, but no frame fitted for more than `stale_after_frames` displayed
//            frames; T' is still drawn (better than the template), fitting again makes it fitted
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "shared/config.h"

namespace rt::hand {

enum class AppearancePhase { Waiting, Fitted, Stale };
const char* appearance_phase_name(AppearancePhase phase);  // "waiting", "fitted", "stale"

// Weight of the next frame's statistics when `fitted_before` frames are already in the state: the
// running mean (1 / (n + 1)) while that exceeds `smoothing`, then `smoothing` (an exponential
// average over about 1 / smoothing frames). The first frame weighs 1. hand_color_reduce.comp and
// its reference compute the same.
double appearance_weight(double fitted_before, double smoothing);

// What one adaption frame did to the statistics.
enum class AdaptionOutcome { Fitted, RegionTooSmall, NotFinite };
const char* adaption_outcome_name(AdaptionOutcome outcome);

struct LabStatistics {
  std::array<double, 3> mean{}, sigma{};  // L, alpha, beta
};

struct AppearanceStatus {
  AppearancePhase phase = AppearancePhase::Waiting;
  uint64_t frames_fitted = 0;            // frames whose statistics are in T'
  bool provisional = false;              // fitted, but only from frames with the hand inside d_max
  uint64_t frames_tried = 0;             // adaption frames run on a tracked hand
  uint64_t frames_region_too_small = 0;  // of those, too few pixels where portrait and mesh agree
  uint64_t frames_not_finite = 0;        // of those, statistics that were not finite
  uint64_t frames_displayed = 0;
  std::optional<uint64_t> frames_since_fit;          // displayed frames since the last fitted one
  std::optional<uint64_t> first_fit_display_frame;   // frames displayed when the first one fitted
  double last_region_pixels = 0;                     // pixels counted in the last frame tried
  double min_region_pixels = 0;
  uint64_t stale_after_frames = 0;
  LabStatistics image, mesh;  // Eq. 3's m_i, sigma_i (portrait) and m_g, sigma_g (template)

  // "waiting: no frame with the hand seen by the cameras yet", "fitted from 12 frames",
  // "fitted from 3 frames, provisional: ...", "stale: last fitted 400 frames ago (fitted from 12
  // frames)".
  std::string describe() const;
  // {"state", "describe", "provisional", "frames_fitted", "frames_tried", "frames_rejected": {"region_too_small",
  // "not_finite"}, "frames_displayed", "frames_since_fit", "first_fit_display_frame",
  // "last_region_pixels", "min_region_pixels", "stale_after_frames", "image": {"mean", "sigma"},
  // "mesh": {...}}; never-known values are null.
  nlohmann::json to_json() const;
};

class AppearanceAdaption {
 public:
  AppearanceAdaption(uint64_t stale_after_frames, double min_region_pixels);

  // The receiver displayed `count` more frames.
  void frame_displayed(uint64_t count = 1);
  // The same from a count kept on another thread: the total so far (a smaller one is ignored).
  void sync_frames_displayed(uint64_t total);
  // Whether a frame with the hand at this side of d_max is to be fitted: beyond it always; inside
  // it only until a frame beyond it has fitted.
  bool accepts(bool hand_beyond_d_max) const { return hand_beyond_d_max || !fitted_beyond_d_max_; }
  // Whether the fit so far must be dropped before this frame (reset(), and T' back to T): the
  // first frame beyond d_max after a provisional fit. The hand is not drawn beyond d_max, so
  // nobody sees the template's skin in between.
  bool restarts_before(bool hand_beyond_d_max) const { return hand_beyond_d_max && provisional(); }
  // One adaption frame: the GPU state just before and just after hand_color_reduce ran on it.
  AdaptionOutcome record(const shader_abi::AppearanceState& before, const shader_abi::AppearanceState& after,
                         bool hand_beyond_d_max = true);
  // T' back to T: waiting again (the displayed-frame count is kept).
  void reset();

  AppearanceStatus status() const;
  // Log entries due since the last call, each the status's JSON plus "change": "fitted" at the
  // first fit, "stale" when a fit grows stale, "refitted" when a stale one fits again, and
  // "rejected" (with "reason") at the first frame refused for each reason.
  std::vector<nlohmann::json> take_events();

 private:
  AppearancePhase phase() const;
  bool provisional() const { return last_fit_at_.has_value() && !fitted_beyond_d_max_; }
  void note_phase_change(AppearancePhase before);
  void push_event(const char* event, const char* reason = nullptr);

  uint64_t stale_after_frames_;
  double min_region_pixels_;
  uint64_t displayed_ = 0, tried_ = 0, too_small_ = 0, not_finite_ = 0;
  std::optional<uint64_t> first_fit_at_, last_fit_at_;
  bool fitted_beyond_d_max_ = false;
  shader_abi::AppearanceState state_{};
  std::vector<nlohmann::json> events_;
};

}  // namespace rt::hand
