// The viewpoint over time: the One-Euro filter, the continuous tracker with its gates, and the
// paper's once-at-start estimate. Measurements are synthetic (truth + noise + injected faults);
// the noise level matches what the eye detector gives on the synthetic renders (a few mm).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <numbers>
#include <random>

#include "viewer/initial_viewpoint.h"
#include "viewer/one_euro_filter.h"
#include "viewer/viewpoint_tracker.h"

namespace {

using rt::TrackerVerdict;

constexpr uint64_t kFrameUs = 33'333;  // 30 fps, the RGBD cameras' rate
// Per-axis noise of a frame's triangulated midpoint: the renders' errors are 1-4 mm.
constexpr double kNoiseM = 0.003;

double smoothstep(double u) {
  u = std::clamp(u, 0.0, 1.0);
  return u * u * (3 - 2 * u);
}

// A seated viewer: still but for a centimetre of sway, leans 12 cm to the side over 0.8 s at
// 3 s, back at 6 s, and 8 cm towards the screen over 1 s at 8 s (peak speed ~0.23 m/s).
Eigen::Vector3d seated_viewer(double t_s) {
  const double tau = 2 * std::numbers::pi;
  return {0.01 * std::sin(tau * 0.2 * t_s) + 0.12 * smoothstep((t_s - 3) / 0.8) - 0.12 * smoothstep((t_s - 6) / 0.8),
          0.005 * std::sin(tau * 0.15 * t_s), 0.7 - 0.08 * smoothstep((t_s - 8) / 1.0)};
}

bool moving_at(double t_s) { return (seated_viewer(t_s) - seated_viewer(t_s - 0.05)).norm() > 0.0015; }

rt::EyePair measured(const Eigen::Vector3d& midpoint, double reprojection_mrad = 2.0) {
  rt::EyePair pair;
  pair.midpoint = midpoint;
  pair.viewer_right = midpoint + Eigen::Vector3d(0.0315, 0, 0);
  pair.viewer_left = midpoint - Eigen::Vector3d(0.0315, 0, 0);
  pair.max_reprojection_mrad = reprojection_mrad;
  return pair;
}

rt::EyePair not_found() {
  rt::EyePair pair;
  pair.failure = rt::ViewerFailure::EyesNotFound;
  pair.message = "no frontal face in the image";
  return pair;
}

}  // namespace

TEST_CASE("One-Euro filter: passes a still value, converges, and lags less when moving", "[viewer][filter]") {
  rt::OneEuroFilter filter;
  const Eigen::Vector3d still(0.1, -0.05, 0.7);
  CHECK(filter.update(still, 0.0) == still);  // the first value passes through, whatever dt
  for (int i = 0; i < 10; ++i) CHECK((filter.update(still, 1.0 / 30) - still).norm() < 1e-15);

  // A ramp at 0.3 m/s: the adaptive cutoff follows it far more closely than the same filter
  // without speed adaptation (a plain 0.5 Hz low-pass).
  rt::OneEuroParameters plain_parameters;
  plain_parameters.speed_coefficient = 0.0;
  rt::OneEuroFilter adaptive, plain(plain_parameters);
  Eigen::Vector3d value = still;
  for (int i = 0; i < 60; ++i) {
    value.x() += 0.3 / 30;
    adaptive.update(value, 1.0 / 30);
    plain.update(value, 1.0 / 30);
  }
  const double adaptive_lag = (value - adaptive.value()).norm(), plain_lag = (value - plain.value()).norm();
  INFO("lag adaptive " << adaptive_lag * 1000 << " mm, plain " << plain_lag * 1000 << " mm");
  CHECK(adaptive_lag < 0.3 * plain_lag);
  CHECK(adaptive.velocity().x() > 0.2);

  CHECK_THROWS_WITH(adaptive.update(value, 0.0), Catch::Contains("dt must be > 0"));
  CHECK_THROWS_WITH(adaptive.update(value, -1.0), Catch::Contains("dt must be > 0"));
  CHECK_THROWS_WITH(adaptive.update(Eigen::Vector3d(NAN, 0, 0.7), 0.03), Catch::Contains("NaN"));
  rt::OneEuroParameters bad;
  bad.min_cutoff_hz = 0;
  CHECK_THROWS_WITH(rt::OneEuroFilter(bad), Catch::Contains("cutoffs must be > 0"));
}

TEST_CASE("tracker: a moving viewer with noise and outliers is smoothed, outliers rejected, never NaN", "[viewer][tracker]") {
  std::mt19937 random(2024);
  std::normal_distribution<double> noise(0.0, kNoiseM);
  // Outliers start at 15 cm: after two frames without an accepted one, the jump gate has widened
  // to 1.5 m/s * 67 ms + 2 cm = 12 cm, and a head could really have moved that far.
  std::uniform_real_distribution<double> jump(0.15, 0.40), unit(-1.0, 1.0);
  rt::ViewpointTracker tracker;

  struct Errors {
    double raw_squared = 0, smoothed_squared = 0;
    int count = 0;
    double raw_rms_mm() const { return 1000 * std::sqrt(raw_squared / count); }
    double smoothed_rms_mm() const { return 1000 * std::sqrt(smoothed_squared / count); }
  } still, moving, all;
  int outliers = 0, outliers_rejected = 0, clean = 0, clean_accepted = 0;
  for (int frame = 0; frame < 330; ++frame) {
    const uint64_t t_us = 1'000'000 + uint64_t(frame) * kFrameUs;
    const double t_s = double(frame) * kFrameUs * 1e-6;
    const Eigen::Vector3d truth = seated_viewer(t_s);
    const Eigen::Vector3d raw = truth + Eigen::Vector3d(noise(random), noise(random), noise(random));
    TrackerVerdict verdict;
    if (frame % 23 == 11) {
      // A wrong detection: an eye in a poster, a nostril in two views.
      Eigen::Vector3d direction(unit(random), unit(random), unit(random));
      direction.z() = std::abs(direction.z());  // in front of the screen, so only the jump gate can catch it
      verdict = tracker.update(t_us, measured(truth + jump(random) * direction.normalized()));
      ++outliers;
      outliers_rejected += verdict == TrackerVerdict::RejectedJump;
    } else if (frame % 31 == 7) {
      verdict = tracker.update(t_us, not_found());
      CHECK(verdict == TrackerVerdict::NotFound);
    } else if (frame % 37 == 5) {
      verdict = tracker.update(t_us, measured(raw, 25.0));
      CHECK(verdict == TrackerVerdict::RejectedReprojection);
    } else {
      verdict = tracker.update(t_us, measured(raw));
      ++clean;
      clean_accepted += verdict == TrackerVerdict::Accepted || verdict == TrackerVerdict::Started;
    }
    const auto latest = tracker.latest();
    REQUIRE(latest);
    REQUIRE(latest->midpoint.allFinite());
    REQUIRE(latest->velocity_m_per_s.allFinite());
    // Compare on frames that were filtered, after the filter's first second of settling.
    if (frame >= 30 && verdict == TrackerVerdict::Accepted) {
      for (Errors* errors : {&all, moving_at(t_s) ? &moving : &still}) {
        errors->raw_squared += (raw - truth).squaredNorm();
        errors->smoothed_squared += (latest->midpoint - truth).squaredNorm();
        ++errors->count;
      }
    }
  }
  std::cout << "tracker on a seated viewer (3 mm noise/axis, 30 fps, 11 s, 12 cm leans): RMS error raw " << all.raw_rms_mm()
            << " mm, smoothed " << all.smoothed_rms_mm() << " mm; still: raw " << still.raw_rms_mm() << ", smoothed "
            << still.smoothed_rms_mm() << "; moving: raw " << moving.raw_rms_mm() << ", smoothed " << moving.smoothed_rms_mm()
            << "; outliers rejected " << outliers_rejected << "/" << outliers << ", clean frames accepted " << clean_accepted
            << "/" << clean << "\n";
  CHECK(outliers_rejected == outliers);
  CHECK(clean_accepted == clean);
  REQUIRE(still.count > 150);
  REQUIRE(moving.count > 40);
  // Smoothing must pay overall, remove most of the jitter while still (what a viewer sees as
  // shimmer), and cost at most a little while moving (lag). Simulated with these defaults over
  // three noise seeds: 38% less overall, 54% less while still, 3% less while moving.
  CHECK(all.smoothed_rms_mm() < 0.8 * all.raw_rms_mm());
  CHECK(still.smoothed_rms_mm() < 0.6 * still.raw_rms_mm());
  CHECK(moving.smoothed_rms_mm() < 1.2 * moving.raw_rms_mm());
}

TEST_CASE("tracker: repeated and backward timestamps are ignored and change nothing", "[viewer][tracker]") {
  rt::ViewpointTracker tracker;
  const Eigen::Vector3d start(0, 0, 0.7);
  CHECK(tracker.update(1000, measured(start)) == TrackerVerdict::Started);
  CHECK(tracker.update(1000 + kFrameUs, measured(start + Eigen::Vector3d(0.005, 0, 0))) == TrackerVerdict::Accepted);
  const rt::TrackedViewpoint before = *tracker.latest();

  CHECK(tracker.update(1000 + kFrameUs, measured(start + Eigen::Vector3d(0.01, 0, 0))) == TrackerVerdict::IgnoredDuplicate);
  CHECK(tracker.update(1000, measured(start)) == TrackerVerdict::IgnoredOutOfOrder);
  CHECK(tracker.update(500, not_found()) == TrackerVerdict::IgnoredOutOfOrder);
  CHECK(tracker.update(0, start, 0.0) == TrackerVerdict::IgnoredOutOfOrder);
  const rt::TrackedViewpoint after = *tracker.latest();
  CHECK(after.midpoint == before.midpoint);
  CHECK(after.velocity_m_per_s == before.velocity_m_per_s);
  CHECK(after.timestamp_us == before.timestamp_us);

  // A frame without eyes still moves time on: the same timestamp afterwards is a duplicate.
  CHECK(tracker.update(1000 + 2 * kFrameUs, not_found()) == TrackerVerdict::NotFound);
  CHECK(tracker.update(1000 + 2 * kFrameUs, measured(start)) == TrackerVerdict::IgnoredDuplicate);
  CHECK(tracker.update(1000 + 3 * kFrameUs, measured(start)) == TrackerVerdict::Accepted);
  CHECK(tracker.latest()->timestamp_us == 1000 + 3 * kFrameUs);
}

TEST_CASE("tracker: invalid measurements are rejected, not filtered", "[viewer][tracker]") {
  rt::ViewpointTracker tracker;
  CHECK_FALSE(tracker.latest());
  CHECK(tracker.lost(0, 500'000));
  CHECK(tracker.update(10, Eigen::Vector3d(NAN, 0, 0.7)) == TrackerVerdict::RejectedInvalid);
  CHECK(tracker.update(20, Eigen::Vector3d(0, 0, 0.0)) == TrackerVerdict::RejectedInvalid);
  CHECK(tracker.update(30, Eigen::Vector3d(0, 0, -0.3)) == TrackerVerdict::RejectedInvalid);
  CHECK(tracker.update(40, Eigen::Vector3d(0, 0, 0.7), NAN) == TrackerVerdict::RejectedInvalid);
  CHECK_FALSE(tracker.latest());
  CHECK(tracker.update(50, Eigen::Vector3d(0, 0, 0.7)) == TrackerVerdict::Started);
  CHECK_FALSE(tracker.lost(50 + 400'000, 500'000));
  CHECK(tracker.lost(50 + 600'000, 500'000));
  CHECK(std::string(rt::verdict_name(TrackerVerdict::RejectedJump)) == "rejected: jump");
}

TEST_CASE("tracker: a viewer who really moves far is re-acquired after a few consistent frames", "[viewer][tracker]") {
  rt::ViewpointTrackerOptions options;
  rt::ViewpointTracker tracker(options);
  uint64_t t = 0;
  for (int i = 0; i < 10; ++i) tracker.update(t += kFrameUs, measured({0, 0, 0.7}));
  // The viewer leans 30 cm to the side between two frames (or the first track was wrong).
  const Eigen::Vector3d moved(0.3, 0, 0.65);
  for (size_t i = 1; i < options.reacquire_after; ++i) CHECK(tracker.update(t += kFrameUs, measured(moved)) == TrackerVerdict::RejectedJump);
  CHECK(tracker.update(t += kFrameUs, measured(moved)) == TrackerVerdict::Reacquired);
  CHECK((tracker.latest()->midpoint - moved).norm() < 1e-12);

  SECTION("scattered wrong detections between good frames neither pass nor re-acquire") {
    std::mt19937 random(5);
    std::uniform_real_distribution<double> lateral(-0.4, 0.4);
    for (int i = 0; i < 20; ++i) {
      const Eigen::Vector3d far_and_random(moved.x() + (i % 2 ? 0.3 : -0.3), lateral(random), 0.7);
      CHECK(tracker.update(t += kFrameUs, measured(far_and_random)) == TrackerVerdict::RejectedJump);
      CHECK(tracker.update(t += kFrameUs, measured(moved)) == TrackerVerdict::Accepted);
    }
    CHECK((tracker.latest()->midpoint - moved).norm() < 1e-9);
  }
}

TEST_CASE("once at start: robust over frames with failures and outliers", "[viewer][initial]") {
  std::mt19937 random(99);
  std::normal_distribution<double> noise(0.0, kNoiseM);
  const Eigen::Vector3d truth(-0.04, 0.06, 0.72);
  rt::InitialViewpointOptions options;
  rt::InitialViewpointEstimator estimator(options);
  uint64_t t = 0;
  for (size_t i = 0; i + 1 < options.frames_needed; ++i)
    estimator.add(t += kFrameUs, measured(truth + Eigen::Vector3d(noise(random), noise(random), noise(random))));
  const rt::InitialViewpoint early = estimator.result();
  CHECK(early.failure == rt::ViewerFailure::TooFewFrames);
  CHECK_THAT(early.message, Catch::Contains(std::to_string(options.frames_needed - 1) + " frame(s)"));

  for (int i = 0; i < 4; ++i) estimator.add(t += kFrameUs, not_found());
  for (int i = 0; i < 4; ++i) estimator.add(t += kFrameUs, measured(truth + Eigen::Vector3d(0.12, -0.05 * i, 0.0)));
  for (int i = 0; i < 6; ++i)
    estimator.add(t += kFrameUs, measured(truth + Eigen::Vector3d(noise(random), noise(random), noise(random))));
  const rt::InitialViewpoint result = estimator.result();
  INFO(result.message);
  REQUIRE(result.ok());
  CHECK(result.frames_outliers == 4);
  CHECK(result.frames_without_eyes == 4);
  CHECK(result.frames_used == options.frames_needed - 1 + 6);
  // 20 frames of 3 mm noise average to well under 2 mm.
  CHECK((result.midpoint - truth).norm() < 0.002);
  CHECK(result.timestamp_us == t);
}

TEST_CASE("once at start: a drifting viewer is reported as unsteady, not averaged", "[viewer][initial]") {
  rt::InitialViewpointEstimator estimator;
  // 56 mm of drift over a second: every frame lies within the 3 cm outlier distance of the
  // median, but together they spread 16 mm RMS, more than the 15 mm a still head shows.
  for (int i = 0; i < 30; ++i) estimator.add(uint64_t(i) * kFrameUs, measured({-0.028 + 0.056 * i / 29.0, 0.0, 0.7}));
  const rt::InitialViewpoint result = estimator.result();
  CHECK(result.failure == rt::ViewerFailure::Unsteady);
  CHECK_THAT(result.message, Catch::Contains("continuous tracker"));
  CHECK(result.midpoint.allFinite());
  CHECK(std::string(rt::failure_name(result.failure)) == "unsteady");
}
