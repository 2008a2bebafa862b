// The remote hand carried forward to its display time (tracking/skeleton_prediction.h).
#include <catch2/catch.hpp>

#include <Eigen/Geometry>

#include <cmath>
#include <limits>
#include <vector>

#include "support/hands.h"
#include "tracking/skeleton_prediction.h"

using namespace rt;
using rt::test::flat_hand;

namespace {

// A hand whose joints all follow `position(t)` offset as flat_hand lays them out.
template <class Path>
std::vector<HandSkeleton> samples(Path position, uint64_t from_us, uint64_t to_us, uint64_t step_us = 20'000) {
  std::vector<HandSkeleton> out;
  for (uint64_t t = from_us; t <= to_us; t += step_us) {
    const Eigen::Vector3d p = position(double(t) * 1e-6);
    HandSkeleton hand = flat_hand(p.x(), p.y(), p.z(), t);
    hand.elbow = hand.wrist + Eigen::Vector3d(0, -0.25, 0.1);
    out.push_back(hand);
  }
  return out;
}

std::vector<Eigen::Vector3d> joints(const HandSkeleton& hand) {
  std::vector<Eigen::Vector3d> all = hand.hand_joints();
  all.push_back(hand.elbow);
  return all;
}

double largest_difference(const HandSkeleton& a, const HandSkeleton& b) {
  const auto ja = joints(a), jb = joints(b);
  double largest = 0;
  for (size_t i = 0; i < ja.size(); ++i) largest = std::max(largest, (ja[i] - jb[i]).norm());
  return largest;
}

}  // namespace

TEST_CASE("a hand at rest stays where it was last seen") {
  const auto history = samples([](double) { return Eigen::Vector3d(0.05, 0.02, 0.3); }, 0, 200'000);
  const auto predicted = predict_hand(history, 300'000);
  REQUIRE(predicted);
  CHECK(largest_difference(*predicted, history.back()) < 1e-12);
  CHECK(predicted->timestamp_us == 300'000);
}

TEST_CASE("a hand at constant velocity is carried forward exactly") {
  const Eigen::Vector3d v(0.3, -0.1, -0.8);
  auto path = [&](double t) { return Eigen::Vector3d(Eigen::Vector3d(0, 0, 0.4) + v * t); };
  const auto history = samples(path, 0, 200'000);
  const auto predicted = predict_hand(history, 300'000);
  REQUIRE(predicted);
  const auto truth = samples(path, 300'000, 300'000).front();
  CHECK(largest_difference(*predicted, truth) < 1e-9);
}

TEST_CASE("a hand that slows down is predicted nearer the truth than held") {
  // Slowing onto the glass: z = 0.2 - 0.6 t + 0.75 t^2 until it stops at t = 0.4 s (z = 0.08).
  auto path = [](double t) { return Eigen::Vector3d(0, 0, 0.2 - 0.6 * t + 0.75 * t * t); };
  const auto history = samples(path, 0, 200'000);
  const auto predicted = predict_hand(history, 300'000);
  REQUIRE(predicted);
  const auto truth = samples(path, 300'000, 300'000).front();
  CHECK(largest_difference(*predicted, truth) < 0.5 * largest_difference(history.back(), truth));
}

TEST_CASE("speed and lead are clamped to what a hand can do") {
  SkeletonPredictionParameters parameters;
  parameters.max_speed_m_s = 1.0;
  parameters.max_lead_us = 100'000;
  // 5 m/s sideways (tracker noise, a swapped hand): at most 1 m/s for at most 100 ms.
  auto path = [](double t) { return Eigen::Vector3d(5.0 * t, 0, 0.3); };
  const auto history = samples(path, 0, 100'000);
  const auto predicted = predict_hand(history, 1'100'000, parameters);
  REQUIRE(predicted);
  CHECK(predicted->palm.x() - history.back().palm.x() == Approx(0.1).margin(1e-9));
  CHECK_THROWS_WITH(predict_hand(history, 0, SkeletonPredictionParameters{.history_us = 0}),
                    Catch::Contains("history"));
}

TEST_CASE("no joint is ever predicted behind the glass") {
  // Fast at the glass: the fit would carry it 8 cm through.
  auto path = [](double t) { return Eigen::Vector3d(0, 0, 0.1 - 0.8 * t); };
  const auto history = samples(path, 0, 100'000);
  for (const uint64_t at : {100'000u, 150'000u, 200'000u, 400'000u}) {
    const auto predicted = predict_hand(history, at);
    REQUIRE(predicted);
    for (const Eigen::Vector3d& joint : joints(*predicted)) CHECK(joint.z() >= 0.0);
  }
  // A sample the tracker reported just behind it is put back on it.
  std::vector<HandSkeleton> behind = {flat_hand(0, 0, -0.002, 0)};
  CHECK(predict_hand(behind, 0)->palm.z() == 0.0);
}

TEST_CASE("no history or NaN joints give no NaN") {
  CHECK_FALSE(predict_hand({}, 100'000).has_value());
  auto path = [](double t) { return Eigen::Vector3d(0.1 * t, 0, 0.3 - 0.2 * t); };
  auto history = samples(path, 0, 100'000);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  history[1].palm = Eigen::Vector3d::Constant(nan);  // a glitch in an older sample
  history[2].digits[1][4].x() = nan;
  const auto predicted = predict_hand(history, 160'000);
  REQUIRE(predicted);
  for (const Eigen::Vector3d& joint : joints(*predicted)) CHECK(joint.allFinite());
  CHECK(predicted->palm.x() == Approx(0.016).margin(1e-9));
  // A joint the newest sample lacks (no elbow: no forearm) stays absent, and spreads to nothing.
  history.back().elbow = Eigen::Vector3d::Constant(nan);
  const auto without_elbow = predict_hand(history, 160'000);
  CHECK_FALSE(without_elbow->has_elbow());
  for (const Eigen::Vector3d& joint : without_elbow->hand_joints()) CHECK(joint.allFinite());
  // A single sample is held where it is.
  const auto single = predict_hand(std::span(history).first(1), 500'000);
  CHECK(largest_difference(*single, history.front()) < 1e-12);
}

TEST_CASE("a turning hand keeps its bones' lengths") {
  // The hand turns about its wrist at 2 rad/s while moving: each joint alone would cut the arc.
  auto hand_at = [](double t) {
    HandSkeleton hand = flat_hand(0, 0, 0.3, uint64_t(std::llround(t * 1e6)));
    const Eigen::AngleAxisd turn(2.0 * t, Eigen::Vector3d::UnitZ());
    const Eigen::Vector3d wrist = hand.wrist;
    auto place = [&](Eigen::Vector3d& p) { p = wrist + turn * (p - wrist) + Eigen::Vector3d(0.2 * t, 0, 0); };
    place(hand.palm);
    for (auto& digit : hand.digits)
      for (auto& joint : digit) place(joint);
    hand.wrist += Eigen::Vector3d(0.2 * t, 0, 0);
    return hand;
  };
  std::vector<HandSkeleton> history;
  for (int i = 0; i <= 5; ++i) history.push_back(hand_at(0.02 * i));
  const auto predicted = predict_hand(history, 250'000);
  REQUIRE(predicted);
  const HandSkeleton& newest = history.back();
  for (int d = 0; d < kDigitCount; ++d)
    for (int j = 1; j < kJointsPerDigit; ++j)
      CHECK((predicted->digits[d][j] - predicted->digits[d][j - 1]).norm() ==
            Approx((newest.digits[d][j] - newest.digits[d][j - 1]).norm()).margin(1e-9));
}

TEST_CASE("a hand at rest under the tracker's noise is held, not sent drifting") {
  // Every joint off by up to 1.5 mm in each sample, in a fixed pattern: no motion at all.
  std::vector<HandSkeleton> history;
  for (int i = 0; i <= 8; ++i) {
    HandSkeleton hand = flat_hand(0.02, 0.0, 0.005, uint64_t(i) * 20'000);
    const double wobble = 0.0015 * ((i * 7) % 5 - 2) / 2.0;
    hand.palm.x() += wobble;
    for (auto& digit : hand.digits)
      for (auto& joint : digit) joint.y() -= wobble;
    history.push_back(hand);
  }
  const auto predicted = predict_hand(history, history.back().timestamp_us + 100'000);
  REQUIRE(predicted);
  CHECK(largest_difference(*predicted, history.back()) < 1e-12);
}
