// Appearance adaption's state machine (hand/appearance_adaption.h), on the CPU with the
// hand_color_reduce reference standing in for the GPU: waiting until a frame fits, a region too
// small never counts, stale after K displayed frames without a fit whatever the wall time, fitted
// again by one good frame; and a receiver at 1 frame/s and one at 30, playing the same scene
// timeline (far 2 s, at the glass 10 s, far 1 s), end in states that depend on frames only: the
// same frames give bit-identical statistics, and staleness follows the displayed-frame count (10
// frames at the glass at 1 frame/s stay fitted, 300 at 30 go stale after K), not seconds.
#include <catch2/catch.hpp>

#include <cmath>
#include <random>
#include <vector>

#include "hand/appearance_adaption.h"
#include "passes/hand_color_reduce.h"

using namespace rt;
using hand::AdaptionOutcome;
using hand::AppearanceAdaption;
using hand::AppearancePhase;
using shader_abi::AppearanceState;
using shader_abi::ColorStatsPartial;

namespace {

constexpr double kMinPixels = 46.0;  // 2e-4 of 640x360
constexpr float kSmoothing = 0.25f;

// Adaption frame k's statistics as the statistics pass would write them: `pixels` pixels whose
// L-alpha-beta depend on k only (the frame, not the time it is shown at).
std::vector<ColorStatsPartial> frame_partials(uint64_t k, int pixels) {
  std::mt19937 rng(uint32_t(1000 + k));
  std::uniform_real_distribution<float> value(-0.9f, 0.3f);
  std::vector<ColorStatsPartial> partials(4);
  for (int i = 0; i < pixels; ++i) {
    ColorStatsPartial& p = partials[size_t(i) % partials.size()];
    p.count[0] += 1.0f;
    for (int c = 0; c < 3; ++c) {
      const float image = value(rng) * 0.3f - 0.6f, mesh = value(rng) * 0.2f - 0.3f;
      p.image_sum[c] += image;
      p.image_sum_sq[c] += image * image;
      p.mesh_sum[c] += mesh;
      p.mesh_sum_sq[c] += mesh * mesh;
    }
  }
  return partials;
}

// A receiver: the state machine plus the reduce (its reference) that it reads back after each frame.
struct Receiver {
  explicit Receiver(uint64_t stale_frames) : adaption(stale_frames, kMinPixels) {}
  AdaptionOutcome adapt(const std::vector<ColorStatsPartial>& partials, bool beyond_d_max = true) {
    const shader_abi::ColorStatsReduceParams params{uint32_t(partials.size()), float(kMinPixels), kSmoothing, 0.01f};
    const AppearanceState after = passes::color_reduce_reference(partials, gpu, params);
    const AdaptionOutcome outcome = adaption.record(gpu, after, beyond_d_max);
    gpu = after;
    return outcome;
  }
  AppearanceAdaption adaption;
  AppearanceState gpu{};
};

// A scene timeline in seconds, like clap: the hand beyond d_max and well seen for the first 2 s,
// at the glass for 10 s, beyond d_max again for the last second.
bool hand_far(double t_s) { return t_s < 2.0 || t_s >= 12.0; }
constexpr double kSceneS = 13.0;

struct Played {
  AppearanceState state{};
  hand::AppearanceStatus status;
  std::vector<AppearanceState> after_each_fit;  // the state after the n-th fitted frame
  std::optional<uint64_t> stale_at_frame;       // displayed frames when it first went stale
  std::vector<std::string> events;
};

// Plays the timeline at `fps` displayed frames per second: each displayed frame with the hand far
// is an adaption frame (the n-th such frame carries frame_partials(n)).
Played play(double fps, uint64_t stale_frames) {
  Receiver receiver(stale_frames);
  Played played;
  uint64_t adaption_frames = 0;
  const auto frames = uint64_t(std::llround(kSceneS * fps));
  for (uint64_t i = 0; i < frames; ++i) {
    // As in the receiver: a frame is displayed, then the hand thread adapts from it.
    receiver.adaption.frame_displayed();
    if (!played.stale_at_frame && receiver.adaption.status().phase == AppearancePhase::Stale)
      played.stale_at_frame = receiver.adaption.status().frames_displayed;
    if (hand_far(double(i) / fps) && receiver.adapt(frame_partials(adaption_frames++, 400)) == AdaptionOutcome::Fitted)
      played.after_each_fit.push_back(receiver.gpu);
  }
  for (const auto& event : receiver.adaption.take_events()) played.events.push_back(event["change"]);
  played.state = receiver.gpu;
  played.status = receiver.adaption.status();
  return played;
}

bool same_state(const AppearanceState& a, const AppearanceState& b) {
  return a.header == b.header && a.image_mean == b.image_mean && a.image_sigma == b.image_sigma && a.mesh_mean == b.mesh_mean &&
         a.mesh_sigma == b.mesh_sigma;
}

}  // namespace

TEST_CASE("appearance weight: the running mean of the first frames, then the smoothing, by frame count") {
  CHECK(hand::appearance_weight(0, 0.25) == 1.0);
  CHECK(hand::appearance_weight(1, 0.25) == 0.5);
  CHECK(hand::appearance_weight(3, 0.25) == 0.25);
  CHECK(hand::appearance_weight(100, 0.25) == 0.25);
  CHECK(hand::appearance_weight(0, 0.0) == 1.0);       // never smoothed away: the first frame still counts
  CHECK(hand::appearance_weight(1e6, 0.0) == Approx(1e-6).epsilon(1e-3));
  CHECK(hand::appearance_weight(5, 1.0) == 1.0);       // smoothing 1: only the newest frame
  CHECK(hand::appearance_weight(-3, 0.25) == 1.0);     // a broken count is the first frame
}

TEST_CASE("appearance adaption waits until a frame fits, and says so") {
  Receiver receiver(30);
  hand::AppearanceStatus status = receiver.adaption.status();
  CHECK(status.phase == AppearancePhase::Waiting);
  CHECK(status.describe() == "waiting: no frame with the hand seen by the cameras yet");
  receiver.adaption.frame_displayed(500);  // never stale without a fit
  status = receiver.adaption.status();
  CHECK(status.phase == AppearancePhase::Waiting);
  CHECK_FALSE(status.frames_since_fit);
  const nlohmann::json json = status.to_json();
  CHECK(json["state"] == "waiting");
  CHECK(json["frames_fitted"] == 0);
  CHECK(json["frames_displayed"] == 500);
  CHECK(json["image"].is_null());
  CHECK(json["frames_since_fit"].is_null());
  CHECK(json["last_region_pixels"].is_null());
  CHECK(receiver.adaption.take_events().empty());
}

TEST_CASE("a region too small does not count as fitted") {
  Receiver receiver(30);
  CHECK(receiver.adapt(frame_partials(0, 45)) == AdaptionOutcome::RegionTooSmall);
  CHECK(receiver.adapt(frame_partials(1, 0)) == AdaptionOutcome::RegionTooSmall);
  hand::AppearanceStatus status = receiver.adaption.status();
  CHECK(status.phase == AppearancePhase::Waiting);
  CHECK(status.frames_fitted == 0);
  CHECK(status.frames_tried == 2);
  CHECK(status.frames_region_too_small == 2);
  CHECK(status.last_region_pixels == 0.0);
  CHECK_THAT(status.describe(), Catch::StartsWith("waiting: no frame with the hand seen by the cameras") &&
                                    Catch::Contains("2 tried") && Catch::Contains("fewer than 46 pixels"));
  auto events = receiver.adaption.take_events();
  REQUIRE(events.size() == 1);  // the first refusal for a reason, not every one
  CHECK(events[0]["change"] == "rejected");
  CHECK(events[0]["reason"] == "region_too_small");

  CHECK(receiver.adapt(frame_partials(2, 46)) == AdaptionOutcome::Fitted);
  status = receiver.adaption.status();
  CHECK(status.phase == AppearancePhase::Fitted);
  CHECK(status.describe() == "fitted from 1 frame");
  // A small region after a fit keeps the fit (T' unchanged) and does not refresh it.
  receiver.adaption.frame_displayed(10);
  const AppearanceState fitted = receiver.gpu;
  CHECK(receiver.adapt(frame_partials(3, 10)) == AdaptionOutcome::RegionTooSmall);
  CHECK(receiver.gpu.image_mean == fitted.image_mean);
  CHECK(receiver.adaption.status().frames_fitted == 1);
  CHECK(receiver.adaption.status().frames_since_fit == 10u);

  SECTION("statistics that are not finite do not count either") {
    std::vector<ColorStatsPartial> broken = frame_partials(4, 400);
    broken[1].image_sum[2] = std::numeric_limits<float>::infinity();
    CHECK(receiver.adapt(broken) == AdaptionOutcome::NotFinite);
    CHECK(receiver.adaption.status().frames_not_finite == 1);
    CHECK(receiver.adaption.status().frames_fitted == 1);
  }
}

TEST_CASE("a hand never seen beyond d_max fits provisionally, until the first frame beyond it starts afresh") {
  Receiver receiver(30);
  CHECK(receiver.adaption.accepts(false));
  CHECK(receiver.adaption.accepts(true));
  CHECK_FALSE(receiver.adaption.restarts_before(true));  // nothing to drop yet

  REQUIRE(receiver.adapt(frame_partials(0, 400), false) == AdaptionOutcome::Fitted);
  REQUIRE(receiver.adapt(frame_partials(1, 400), false) == AdaptionOutcome::Fitted);
  hand::AppearanceStatus status = receiver.adaption.status();
  CHECK(status.phase == AppearancePhase::Fitted);
  CHECK(status.provisional);
  CHECK(status.frames_fitted == 2);
  CHECK_THAT(status.describe(), Catch::StartsWith("fitted from 2 frames, provisional: the hand was never seen beyond 0.4 m"));
  CHECK(status.to_json()["provisional"] == true);
  CHECK(receiver.adaption.accepts(false));  // more of the arm refines it
  CHECK_FALSE(receiver.adaption.restarts_before(false));
  CHECK(receiver.adaption.restarts_before(true));
  receiver.adaption.frame_displayed(31);
  CHECK_THAT(receiver.adaption.status().describe(), Catch::EndsWith("(fitted from 2 frames, provisional)"));

  // The receiver drops the provisional fit (the GPU state too) before the first frame beyond d_max.
  receiver.adaption.reset();
  receiver.gpu = {};
  REQUIRE(receiver.adapt(frame_partials(2, 400), true) == AdaptionOutcome::Fitted);
  status = receiver.adaption.status();
  CHECK_FALSE(status.provisional);
  CHECK(status.frames_fitted == 1);  // the first full view weighs 1: nothing of the arm-only fit is left
  CHECK(status.describe() == "fitted from 1 frame");
  {
    Receiver fresh(30);
    fresh.adapt(frame_partials(2, 400), true);
    CHECK(same_state(receiver.gpu, fresh.gpu));
  }
  // From now on only frames beyond d_max are used, and nothing restarts.
  CHECK_FALSE(receiver.adaption.accepts(false));
  CHECK(receiver.adaption.accepts(true));
  CHECK_FALSE(receiver.adaption.restarts_before(true));
  receiver.adaption.frame_displayed(100);
  CHECK(receiver.adaption.status().phase == AppearancePhase::Stale);
  CHECK_FALSE(receiver.adaption.accepts(false));  // stale, but a full view's fit still beats the arm's

  SECTION("a provisional frame that is rejected leaves it waiting, and frames inside d_max still count") {
    Receiver r(30);
    CHECK(r.adapt(frame_partials(0, 10), false) == AdaptionOutcome::RegionTooSmall);
    CHECK(r.adaption.status().phase == AppearancePhase::Waiting);
    CHECK_FALSE(r.adaption.status().provisional);
    CHECK(r.adaption.accepts(false));
    CHECK_FALSE(r.adaption.restarts_before(true));
  }
}

TEST_CASE("stale after K displayed frames without a fit, fitted again by one frame") {
  Receiver receiver(20);
  REQUIRE(receiver.adapt(frame_partials(0, 400)) == AdaptionOutcome::Fitted);
  REQUIRE(receiver.adapt(frame_partials(1, 400)) == AdaptionOutcome::Fitted);
  receiver.adaption.frame_displayed(20);
  CHECK(receiver.adaption.status().phase == AppearancePhase::Fitted);
  receiver.adaption.frame_displayed();
  hand::AppearanceStatus status = receiver.adaption.status();
  CHECK(status.phase == AppearancePhase::Stale);
  CHECK(status.describe() == "stale: last fitted 21 frames ago (fitted from 2 frames)");
  CHECK(status.to_json()["image"]["mean"].size() == 3);
  // Counts from another thread: a total, never backwards.
  receiver.adaption.sync_frames_displayed(400);
  receiver.adaption.sync_frames_displayed(10);
  CHECK(receiver.adaption.status().frames_since_fit == 400u);
  CHECK(receiver.adapt(frame_partials(2, 400)) == AdaptionOutcome::Fitted);
  status = receiver.adaption.status();
  CHECK(status.phase == AppearancePhase::Fitted);
  CHECK(status.frames_fitted == 3);
  CHECK(status.frames_since_fit == 0u);
  CHECK(status.first_fit_display_frame == 0u);
  std::vector<std::string> events;
  for (const auto& e : receiver.adaption.take_events()) events.push_back(e["change"]);
  CHECK(events == std::vector<std::string>{"fitted", "stale", "refitted"});

  receiver.adaption.reset();
  CHECK(receiver.adaption.status().phase == AppearancePhase::Waiting);
  CHECK(receiver.adaption.status().frames_displayed == 400);
}

TEST_CASE("appearance adaption at 1 frame/s and at 30 frames/s depends on frames, not seconds") {
  constexpr uint64_t kStale = 20;
  const Played slow = play(1.0, kStale), fast = play(30.0, kStale);

  // The far phases: 2 + 1 adaption frames at 1 frame/s, 60 + 30 at 30.
  CHECK(slow.status.frames_fitted == 3);
  CHECK(fast.status.frames_fitted == 90);
  // The same frames give the same statistics, bit for bit, whatever the frame rate.
  for (size_t n = 0; n < slow.after_each_fit.size(); ++n) {
    INFO("fitted frame " << n);
    CHECK(same_state(slow.after_each_fit[n], fast.after_each_fit[n]));
  }
  // The first 1 / smoothing frames are averaged: frames 0-3 weigh the same.
  {
    Receiver r(kStale);
    double mean_of_means = 0;
    for (uint64_t k = 0; k < 4; ++k) {
      const auto partials = frame_partials(k, 400);
      double sum = 0, n = 0;
      for (const auto& p : partials) sum += p.image_sum[0], n += p.count[0];
      mean_of_means += sum / n / 4.0;
      r.adapt(partials);
    }
    CHECK(r.gpu.image_mean[0] == Approx(mean_of_means).margin(1e-6));
    CHECK(same_state(r.gpu, fast.after_each_fit[3]));
  }

  // Ten seconds at the glass: 10 displayed frames at 1 frame/s (under K), 300 at 30 (over K).
  CHECK_FALSE(slow.stale_at_frame);
  REQUIRE(fast.stale_at_frame);
  CHECK(*fast.stale_at_frame == 60 + kStale + 1);  // K frames after the last fit (frame 60), 2.7 s into the scene
  CHECK(slow.events == std::vector<std::string>{"fitted"});
  CHECK(fast.events == std::vector<std::string>{"fitted", "stale", "refitted"});
  // Both end fitted, from their last frame.
  CHECK(slow.status.phase == AppearancePhase::Fitted);
  CHECK(fast.status.phase == AppearancePhase::Fitted);
  CHECK(slow.status.frames_since_fit == 0u);
  CHECK(fast.status.frames_since_fit == 0u);
  CHECK(slow.status.first_fit_display_frame == 1u);
  CHECK(fast.status.first_fit_display_frame == 1u);
}
