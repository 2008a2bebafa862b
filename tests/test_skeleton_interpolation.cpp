// The remote hands at a portrait's capture time, from the 50 Hz skeleton history: one sample,
// gaps over the limit, out-of-order arrivals, hands that appear or vanish between samples, the
// exactness of the interpolation, and missing (NaN) joints.
#include <catch2/catch.hpp>

#include <Eigen/Geometry>

#include <cmath>
#include <random>
#include <vector>

#include "support/hands.h"
#include "tracking/skeleton_interpolation.h"

using namespace rt;

namespace {

constexpr uint64_t kMs = 1000;

HandSkeleton hand_at_skeleton_interpolation(double x, uint64_t t_us, int32_t id = 1, bool is_left = false) {
  HandSkeleton hand = test::flat_hand(x, 0.1, 0.3, t_us);
  hand.id = id;
  hand.is_left = is_left;
  return hand;
}

SkeletonSample sample(uint64_t t_us, std::vector<HandSkeleton> hands) { return {t_us, std::move(hands)}; }

bool all_finite_skeleton_interpolation(const HandSkeleton& hand) {
  bool finite = hand.direction.allFinite() && hand.palm_normal.allFinite() && hand.elbow.allFinite() &&
                std::isfinite(hand.confidence);
  for (const auto& joint : hand.hand_joints()) finite = finite && joint.allFinite();
  return finite;
}

void require_close_skeleton_interpolation(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double tolerance = 1e-12) {
  INFO("got " << a.transpose() << ", expected " << b.transpose());
  REQUIRE((a - b).norm() <= tolerance);
}

void require_same_joints(const HandSkeleton& a, const HandSkeleton& b, double tolerance = 1e-12) {
  require_close_skeleton_interpolation(a.wrist, b.wrist, tolerance);
  require_close_skeleton_interpolation(a.palm, b.palm, tolerance);
  for (size_t d = 0; d < a.digits.size(); ++d)
    for (size_t j = 0; j < a.digits[d].size(); ++j) require_close_skeleton_interpolation(a.digits[d][j], b.digits[d][j], tolerance);
}

// The hand rigidly moved: rotated by `rotation` about its palm, then shifted.
HandSkeleton moved(const HandSkeleton& hand, const Eigen::Matrix3d& rotation, const Eigen::Vector3d& shift) {
  HandSkeleton out = hand;
  auto place = [&](const Eigen::Vector3d& p) { return Eigen::Vector3d(rotation * (p - hand.palm) + hand.palm + shift); };
  out.wrist = place(hand.wrist);
  out.palm = place(hand.palm);
  out.elbow = place(hand.elbow);
  for (auto& digit : out.digits)
    for (auto& joint : digit) joint = place(joint);
  out.direction = rotation * hand.direction;
  out.palm_normal = rotation * hand.palm_normal;
  return out;
}

}  // namespace

TEST_CASE("skeleton interpolation: one sample holds within the limit, before and after it") {
  const HandSkeleton hand = hand_at_skeleton_interpolation(0.0, 500 * kMs);
  const std::vector<SkeletonSample> samples{sample(500 * kMs, {hand})};
  for (const int64_t offset_ms : {0, -40, 40, -100, 100}) {
    INFO("offset " << offset_ms << " ms");
    const HandsAtTime at = hands_at(samples, uint64_t(int64_t(500 * kMs) + offset_ms * int64_t(kMs)));
    REQUIRE_FALSE(at.stale());
    REQUIRE(at.hands.size() == 1);
    REQUIRE_FALSE(at.interpolated[0]);
    REQUIRE(at.gap_us[0] == uint64_t(std::abs(offset_ms)) * kMs);
    REQUIRE(at.hands[0].timestamp_us == 500 * kMs);  // the moment the held pose shows
    require_same_joints(at.hands[0], hand, 0.0);
  }
  for (const int64_t offset_ms : {-101, 101, -400, 400}) {
    INFO("offset " << offset_ms << " ms");
    const HandsAtTime at = hands_at(samples, uint64_t(int64_t(500 * kMs) + offset_ms * int64_t(kMs)));
    REQUIRE(at.stale());
    REQUIRE(at.hands.empty());
    REQUIRE(at.nearest_sample_gap_us == uint64_t(std::abs(offset_ms)) * kMs);
  }
  REQUIRE(hands_at(samples, 0).stale());  // long before: no pose rather than a stale one
}

TEST_CASE("skeleton interpolation: no samples at all is stale, not an error") {
  const HandsAtTime at = hands_at({}, 1234);
  REQUIRE(at.stale());
  REQUIRE_FALSE(at.nearest_sample_gap_us);
  REQUIRE(at.hands.empty());
}

TEST_CASE("skeleton interpolation: a gap over 100 ms gives no hand in its middle, the near sample at its ends") {
  const HandSkeleton first = hand_at_skeleton_interpolation(0.0, 1000 * kMs), second = hand_at_skeleton_interpolation(0.3, 1300 * kMs);
  const std::vector<SkeletonSample> samples{sample(1000 * kMs, {first}), sample(1300 * kMs, {second})};
  SECTION("the middle: nothing within the limit") {
    const HandsAtTime at = hands_at(samples, 1150 * kMs);
    REQUIRE(at.stale());
    REQUIRE(at.hands.empty());
    REQUIRE(at.nearest_sample_gap_us == 150 * kMs);
  }
  SECTION("near the first: that sample alone, not blended across the gap") {
    const HandsAtTime at = hands_at(samples, 1060 * kMs);
    REQUIRE(at.hands.size() == 1);
    REQUIRE_FALSE(at.interpolated[0]);
    REQUIRE(at.gap_us[0] == 60 * kMs);
    require_same_joints(at.hands[0], first, 0.0);
  }
  SECTION("near the second") {
    const HandsAtTime at = hands_at(samples, 1210 * kMs);
    REQUIRE(at.hands.size() == 1);
    REQUIRE_FALSE(at.interpolated[0]);
    REQUIRE(at.gap_us[0] == 90 * kMs);
    require_same_joints(at.hands[0], second, 0.0);
  }
  SECTION("a limit set wider interpolates across the same gap") {
    const HandsAtTime at = hands_at(samples, 1150 * kMs, 200 * kMs);
    REQUIRE(at.hands.size() == 1);
    REQUIRE(at.interpolated[0]);
    REQUIRE(at.gap_us[0] == 150 * kMs);
    REQUIRE(at.hands[0].palm.x() == Approx(0.15));
  }
}

TEST_CASE("skeleton interpolation: the midpoint of two samples is the hand computed directly") {
  // A hand moving and turning about a fixed axis: positions lerp, the palm's frame turns half-way.
  const HandSkeleton start = hand_at_skeleton_interpolation(0.0, 2000 * kMs);
  const Eigen::Vector3d axis = Eigen::Vector3d(0.3, 1.0, -0.4).normalized();
  const double angle = 0.5;  // radians over 20 ms: a fast turn
  const Eigen::Vector3d shift(0.02, -0.01, -0.03);
  const HandSkeleton end = moved(start, Eigen::AngleAxisd(angle, axis).toRotationMatrix(), shift);
  std::vector<SkeletonSample> samples{sample(2000 * kMs, {start}), sample(2020 * kMs, {end})};
  samples[1].hands[0].timestamp_us = 2020 * kMs;
  samples[1].hands[0].confidence = 0.5f;

  const HandsAtTime at = hands_at(samples, 2010 * kMs);
  REQUIRE(at.hands.size() == 1);
  REQUIRE(at.interpolated[0]);
  REQUIRE(at.gap_us[0] == 10 * kMs);
  const HandSkeleton& mid = at.hands[0];
  REQUIRE(mid.timestamp_us == 2010 * kMs);
  REQUIRE(mid.confidence == Approx(0.75f));
  REQUIRE(mid.id == start.id);
  require_close_skeleton_interpolation(mid.wrist, (start.wrist + end.wrist) / 2);
  require_close_skeleton_interpolation(mid.palm, (start.palm + end.palm) / 2);
  require_close_skeleton_interpolation(mid.elbow, (start.elbow + end.elbow) / 2);
  for (size_t d = 0; d < mid.digits.size(); ++d)
    for (size_t j = 0; j < mid.digits[d].size(); ++j)
      require_close_skeleton_interpolation(mid.digits[d][j], (start.digits[d][j] + end.digits[d][j]) / 2);
  const Eigen::Matrix3d half = Eigen::AngleAxisd(angle / 2, axis).toRotationMatrix();
  require_close_skeleton_interpolation(mid.direction, half * start.direction, 1e-9);
  require_close_skeleton_interpolation(mid.palm_normal, half * start.palm_normal, 1e-9);
  REQUIRE(mid.direction.norm() == Approx(1.0));
  REQUIRE(std::abs(mid.direction.dot(mid.palm_normal)) < 1e-12);

  // Off the midpoint, where turning by s and by 1 - s differ, and where the confidence's ramp
  // and its reverse differ: a quarter and four fifths of the way.
  for (const auto& [t, s] : {std::pair{2005 * kMs, 0.25}, std::pair{2016 * kMs, 0.8}}) {
    INFO("s = " << s);
    const HandsAtTime at_s = hands_at(samples, t);
    REQUIRE(at_s.hands.size() == 1);
    REQUIRE(at_s.interpolated[0]);
    const HandSkeleton& hand = at_s.hands[0];
    require_close_skeleton_interpolation(hand.palm, start.palm * (1 - s) + end.palm * s);
    const Eigen::Matrix3d turned = Eigen::AngleAxisd(angle * s, axis).toRotationMatrix();
    require_close_skeleton_interpolation(hand.direction, turned * start.direction, 1e-9);
    require_close_skeleton_interpolation(hand.palm_normal, turned * start.palm_normal, 1e-9);
    REQUIRE(hand.confidence == Approx(1.0 - 0.5 * s));
  }
  // Exactly at a sample: the sample itself.
  const HandsAtTime exact = hands_at(samples, 2020 * kMs);
  REQUIRE_FALSE(exact.interpolated[0]);
  REQUIRE(exact.gap_us[0] == 0);
  require_same_joints(exact.hands[0], end, 0.0);
}

TEST_CASE("skeleton interpolation: timestamps out of order are kept in time order") {
  SkeletonHistory history(8);
  // Arrivals out of order (a reordering link, a reconnect): 40, 0, 20, 60 ms, and 20 again.
  history.add(sample(40 * kMs, {hand_at_skeleton_interpolation(0.04, 40 * kMs)}));
  history.add(sample(0, {hand_at_skeleton_interpolation(0.0, 0)}));
  history.add(sample(20 * kMs, {hand_at_skeleton_interpolation(0.02, 20 * kMs)}));
  history.add(sample(60 * kMs, {hand_at_skeleton_interpolation(0.06, 60 * kMs)}));
  history.add(sample(20 * kMs, {hand_at_skeleton_interpolation(0.02, 20 * kMs)}));  // a repeat replaces, it does not duplicate
  REQUIRE(history.size() == 4);
  for (const uint64_t t : {5 * kMs, 10 * kMs, 30 * kMs, 45 * kMs, 55 * kMs}) {
    INFO("t " << t);
    const HandsAtTime at = history.at(t);
    REQUIRE(at.hands.size() == 1);
    REQUIRE(at.interpolated[0]);
    REQUIRE(at.gap_us[0] <= 20 * kMs);
    REQUIRE(at.hands[0].palm.x() == Approx(double(t) * 1e-6).margin(1e-12));  // x = t in the samples
  }
  // hands_at itself refuses an unordered span rather than bracketing wrongly.
  const std::vector<SkeletonSample> unordered{sample(40 * kMs, {}), sample(0, {})};
  REQUIRE_THROWS_AS(hands_at(unordered, 10 * kMs), std::invalid_argument);
}

TEST_CASE("skeleton interpolation: a full history drops the oldest, and refuses what is older still") {
  SkeletonHistory history(3);
  for (uint64_t i = 1; i <= 4; ++i) history.add(sample(i * 20 * kMs, {hand_at_skeleton_interpolation(0.0, i * 20 * kMs)}));
  REQUIRE(history.size() == 3);
  REQUIRE(history.at(20 * kMs).nearest_sample_gap_us == 20 * kMs);  // the 20 ms sample went
  history.add(sample(10 * kMs, {}));                                  // older than all kept
  REQUIRE(history.size() == 3);
  REQUIRE(history.at(10 * kMs).nearest_sample_gap_us == 30 * kMs);
}

TEST_CASE("skeleton interpolation: a hand that appears between samples is never blended with nothing") {
  const HandSkeleton right = hand_at_skeleton_interpolation(0.0, 0, 1, false);
  const HandSkeleton left = hand_at_skeleton_interpolation(-0.2, 20 * kMs, 2, true);
  // The right hand is tracked throughout; the left one appears in the later sample.
  const HandSkeleton right_later = hand_at_skeleton_interpolation(0.01, 20 * kMs, 1, false);
  const std::vector<SkeletonSample> samples{sample(0, {right}), sample(20 * kMs, {right_later, left})};
  SECTION("nearer the earlier sample: the right hand interpolated, the left one not there yet") {
    const HandsAtTime at = hands_at(samples, 8 * kMs);
    REQUIRE(at.hands.size() == 1);
    REQUIRE(at.hands[0].id == 1);
    REQUIRE(at.interpolated[0]);
    REQUIRE(at.hands[0].palm.x() == Approx(0.004));
  }
  SECTION("nearer the later sample: the left hand as it is there, unblended") {
    const HandsAtTime at = hands_at(samples, 13 * kMs);
    REQUIRE(at.hands.size() == 2);
    REQUIRE(at.hands[0].id == 1);
    REQUIRE(at.interpolated[0]);
    REQUIRE(at.hands[1].id == 2);
    REQUIRE(at.hands[1].is_left);
    REQUIRE_FALSE(at.interpolated[1]);
    REQUIRE(at.gap_us[1] == 7 * kMs);
    require_same_joints(at.hands[1], left, 0.0);
  }
  SECTION("the same id on the other side is another hand") {
    HandSkeleton flipped = right_later;
    flipped.is_left = true;
    const std::vector<SkeletonSample> swapped{sample(0, {right}), sample(20 * kMs, {flipped})};
    const HandsAtTime at = hands_at(swapped, 8 * kMs);
    REQUIRE(at.hands.size() == 1);
    REQUIRE_FALSE(at.interpolated[0]);
    REQUIRE_FALSE(at.hands[0].is_left);
    require_same_joints(at.hands[0], right, 0.0);
  }
  SECTION("a hand that vanishes: gone once the later sample is nearer") {
    const std::vector<SkeletonSample> vanishing{sample(0, {right}), sample(20 * kMs, {})};
    REQUIRE(hands_at(vanishing, 10 * kMs).hands.size() == 1);  // a tie goes to the earlier sample
    const HandsAtTime at = hands_at(vanishing, 11 * kMs);
    REQUIRE_FALSE(at.stale());  // known: no hand, rather than unknown
    REQUIRE(at.hands.empty());
  }
}

TEST_CASE("skeleton interpolation: a missing elbow stays missing and spoils nothing else") {
  HandSkeleton start = hand_at_skeleton_interpolation(0.0, 0), end = hand_at_skeleton_interpolation(0.02, 20 * kMs);
  const double nan = std::nan("");
  SECTION("missing in both samples") {
    start.elbow = end.elbow = Eigen::Vector3d::Constant(nan);
    const HandSkeleton mid = interpolate_hand(start, end, 0.5);
    REQUIRE(mid.elbow.array().isNaN().all());
    require_close_skeleton_interpolation(mid.palm, (start.palm + end.palm) / 2);
    for (const auto& joint : mid.hand_joints()) REQUIRE(joint.allFinite());
  }
  SECTION("missing in one sample: the nearer sample's elbow, missing or not") {
    end.elbow = Eigen::Vector3d::Constant(nan);
    REQUIRE(interpolate_hand(start, end, 0.25).elbow == start.elbow);
    REQUIRE(interpolate_hand(start, end, 0.75).elbow.array().isNaN().all());
    for (const auto& joint : interpolate_hand(start, end, 0.75).hand_joints()) REQUIRE(joint.allFinite());
  }
  SECTION("through hands_at") {
    start.elbow = end.elbow = Eigen::Vector3d::Constant(nan);
    const std::vector<SkeletonSample> samples{sample(0, {start}), sample(20 * kMs, {end})};
    const HandsAtTime at = hands_at(samples, 10 * kMs);
    REQUIRE(at.hands[0].elbow.array().isNaN().all());
    require_close_skeleton_interpolation(at.hands[0].wrist, (start.wrist + end.wrist) / 2);
  }
}

TEST_CASE("skeleton interpolation: finite inputs never give NaN or Inf, even degenerate palm frames") {
  std::mt19937 rng(19);
  std::uniform_real_distribution<double> unit(-1.0, 1.0), fraction(0.0, 1.0);
  auto random_vector = [&] { return Eigen::Vector3d(unit(rng), unit(rng), unit(rng)); };
  for (int trial = 0; trial < 2000; ++trial) {
    HandSkeleton a = hand_at_skeleton_interpolation(unit(rng), 0), b = hand_at_skeleton_interpolation(unit(rng), 20 * kMs);
    a.direction = random_vector();
    b.direction = random_vector();
    a.palm_normal = random_vector();
    b.palm_normal = random_vector();
    switch (trial % 5) {
      case 0: b.direction = -a.direction, b.palm_normal = -a.palm_normal; break;  // a half turn
      case 1: a.direction = Eigen::Vector3d::Zero(); break;                     // no direction
      case 2: b.palm_normal = b.direction * 2.0; break;                         // parallel to it
      case 3: a.direction = b.direction = Eigen::Vector3d(1e-300, 0, 0); break; // vanishingly small
      default: break;
    }
    const double s = trial % 7 == 0 ? 0.5 : fraction(rng);
    const HandSkeleton mid = interpolate_hand(a, b, s);
    INFO("trial " << trial << " s " << s);
    REQUIRE(all_finite_skeleton_interpolation(mid));
    if (trial % 5 == 4) {
      REQUIRE(mid.direction.norm() == Approx(1.0));
      REQUIRE(mid.palm_normal.norm() == Approx(1.0));
    }
  }
}

TEST_CASE("the hand nearest the screen: in front of its own glass or mapped behind the other's") {
  HandSkeleton far_hand, near_hand, lost_hand;
  far_hand.palm = {0.0, 0.0, 0.30};
  near_hand.palm = {0.1, 0.0, 0.02};
  lost_hand.palm = {0.0, 0.0, std::nan("")};
  std::vector<HandSkeleton> hands = {far_hand, lost_hand, near_hand};
  CHECK(hand_nearest_screen(hands) == &hands[2]);
  // The same hands in the other site's frame: behind its glass, z negated.
  for (HandSkeleton& hand : hands) hand.palm.z() = -hand.palm.z();
  CHECK(hand_nearest_screen(hands) == &hands[2]);
  CHECK(hand_nearest_screen(std::vector<HandSkeleton>{lost_hand}) == nullptr);
}
