// The simulated hand tracker: 50 Hz frames in the device's space that give back the synthetic
// hand within a millimetre (through Leap JSON and the device boundary conversion), and the
// tracker effects at the configured strength: jitter sigma, latency, dropout rate, range.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <vector>

#include "config/assets.h"
#include "geometry/site_frames.h"
#include "sim/leap_json.h"
#include "sim/motion.h"
#include "sim/scene.h"
#include "sim/hand_model.h"
#include "sim/person_mesh.h"
#include "sim/tracker_sim.h"
#include "sim/tracker_space.h"
#include "support/hands.h"

using namespace rt;
using namespace rt::sim;

namespace {

const std::filesystem::path kScenesSimTracker = rt::config::assets_dir() / "scenes";

std::vector<TrackerFrame> all_frames(HandTracker& tracker) {
  std::vector<TrackerFrame> frames;
  while (std::optional<TrackerFrame> frame = tracker.next_frame()) frames.push_back(*frame);
  return frames;
}

Scene clap_with(const TrackerEffects& effects) {
  Scene scene = load_scene(kScenesSimTracker / "clap.json");
  scene.effects.tracker = effects;
  return scene;
}

// The joints the tracker reports with independent noise: palm, wrist, elbow and every digit joint
// except the thumb's carp (it is its mcp) and btip (it is the tip).
std::vector<Eigen::Vector3d> independent_points(const TrackerHand& hand) {
  std::vector<Eigen::Vector3d> points{hand.palm_position, hand.wrist};
  if (hand.elbow) points.push_back(*hand.elbow);
  for (int d = 0; d < kDigitCount; ++d) {
    const TrackerDigit& digit = hand.digits[d];
    if (d != int(Digit::Thumb)) points.push_back(digit.carp);
    for (const Eigen::Vector3d* p : {&digit.mcp, &digit.pip, &digit.dip, &digit.tip}) points.push_back(*p);
  }
  return points;
}

const TrackerHand* find_hand(const TrackerFrame& frame, bool is_left) {
  for (const TrackerHand& hand : frame.hands)
    if (hand.is_left == is_left) return &hand;
  return nullptr;
}

double worst_joint_error(const HandSkeleton& a, const HandSkeleton& b) {
  const auto ja = a.hand_joints(), jb = b.hand_joints();
  REQUIRE(a.has_elbow() == b.has_elbow());
  double worst = a.has_elbow() ? (a.elbow - b.elbow).norm() : 0.0;
  for (size_t i = 0; i < ja.size(); ++i) worst = std::max(worst, (ja[i] - jb[i]).norm());
  return worst;
}

// A hand that is always in front of the default tracker, a palm's breadth above the touch region.
HandSource steady_hand(const TrackerPlacement& placement) {
  return [placement](double) {
    SyntheticHand hand{test::flat_hand(0.1, 0.0, 0.1), 0.085};
    REQUIRE(placement.sees(hand.skeleton.palm));
    return std::vector<SyntheticHand>{hand};
  };
}

}  // namespace

TEST_CASE("effects off: the round trip through tracker space and Leap JSON gives back the synthetic hand",
          "[sim][tracker]") {
  const Scene scene = clap_with({});
  for (Site site : {Site::A, Site::B}) {
    INFO("site " << site_name(site));
    const SiteSetup& setup = scene.at(site);
    const MotionTrack track(setup.motion, setup.site.seat, setup.user);
    SimulatedHandTracker tracker = make_simulated_tracker(scene, site);
    const std::vector<TrackerFrame> frames = all_frames(tracker);
    REQUIRE(frames.size() == tracker_frame_count(scene));
    CHECK(frames.size() == size_t(std::floor(scene.duration_s() * 50)));
    int tracked = 0, touching_tracked = 0, touching = 0;
    std::optional<int32_t> right_id;
    for (size_t i = 0; i < frames.size(); ++i) {
      CHECK(frames[i].timestamp_us == i * 20'000);  // 50 Hz, microseconds
      CHECK(frames[i].id == int64_t(i) + 1);
      const TrackerFrame parsed = parse_leap_json_line(leap_json_line(frames[i]));
      const std::vector<HandSkeleton> hands = skeletons_in_site(parsed, setup.site.tracker);
      const PersonPose truth = track.pose_at(frames[i].timestamp_us * 1e-6);
      const bool on_glass = truth.right_hand.palm.z() < 0.01;
      touching += on_glass;
      for (const TrackerHand& device_hand : parsed.hands) {
        // The device's own space: millimetres, Leap axes (y out of the device), checked against
        // the placement directly rather than through the inverse conversion.
        const Eigen::Vector3d expected_mm = 1000.0 * (setup.site.tracker.tracker_from_site() * truth.right_hand.palm);
        CHECK((device_hand.palm_position - expected_mm).norm() < 1e-3);
        CHECK(device_hand.palm_position.y() > 0.0);
        CHECK(device_hand.palm_position.norm() >= 70.0);
        CHECK(device_hand.palm_position.norm() <= 800.0);
      }
      for (const HandSkeleton& hand : hands) {
        INFO("frame " << i);
        REQUIRE_FALSE(hand.is_left);  // the left hand rests on the lap, out of the tracker's view
        CHECK(worst_joint_error(hand, truth.right_hand) < 1e-3);
        CHECK((hand.palm_normal - truth.right_hand.palm_normal).norm() < 1e-4);
        CHECK((hand.direction - truth.right_hand.direction).norm() < 1e-4);
        CHECK(hand.timestamp_us == frames[i].timestamp_us);
        // The widths the simulated user has: the palm's from the hand's size, the forearm's capsule.
        CHECK(hand.palm_width_m == Approx(palm_width_m(setup.user.hand_scale)).margin(1e-6));
        CHECK(hand.arm_width_m == Approx(kArmWidthM).margin(1e-6));
        // One id for as long as the hand stays tracked.
        if (right_id && !frames[i - 1].hands.empty()) CHECK(hand.id == *right_id);
        right_id = hand.id;
        ++tracked;
        touching_tracked += on_glass;
      }
    }
    CHECK(touching > 25);
    CHECK(touching_tracked == touching);  // the tracker sees every frame of the touch
    CHECK(tracked < int(frames.size()));  // and not the hand at rest on the lap
  }
}

TEST_CASE("tracker_jitter: the measured sigma matches the configured one within 10%", "[sim][tracker]") {
  const Scene clean_scene = clap_with({});
  for (double sigma : {0.5, 2.0}) {
    TrackerEffects effects;
    effects.jitter = TrackerJitter{sigma};
    const Scene noisy_scene = clap_with(effects);
    SimulatedHandTracker clean_tracker = make_simulated_tracker(clean_scene, Site::A);
    SimulatedHandTracker noisy_tracker = make_simulated_tracker(noisy_scene, Site::A);
    const std::vector<TrackerFrame> clean = all_frames(clean_tracker), noisy = all_frames(noisy_tracker);
    REQUIRE(clean.size() == noisy.size());
    double sum = 0, sum_squares = 0;
    size_t count = 0;
    for (size_t i = 0; i < clean.size(); ++i) {
      REQUIRE(clean[i].hands.size() == noisy[i].hands.size());  // jitter does not change what is tracked
      for (size_t h = 0; h < clean[i].hands.size(); ++h) {
        const auto a = independent_points(clean[i].hands[h]), b = independent_points(noisy[i].hands[h]);
        for (size_t p = 0; p < a.size(); ++p)
          for (int axis = 0; axis < 3; ++axis) {
            const double e = b[p][axis] - a[p][axis];
            sum += e;
            sum_squares += e * e;
            ++count;
          }
        const TrackerDigit& thumb = noisy[i].hands[h].digits[0];
        CHECK(thumb.carp == thumb.mcp);  // the tracker's hand model survives the noise
      }
    }
    REQUIRE(count > 5000);
    const double mean = sum / count;
    const double measured = std::sqrt(sum_squares / count - mean * mean);
    INFO("configured " << sigma << " mm, measured " << measured << " mm over " << count << " samples");
    CHECK(std::abs(measured - sigma) < 0.1 * sigma);
    CHECK(std::abs(mean) < 0.05 * sigma);
  }
}

TEST_CASE("tracker_latency: a frame stamped t shows the hand at t minus the delay", "[sim][tracker]") {
  const Scene clean_scene = clap_with({});
  SimulatedHandTracker clean_tracker = make_simulated_tracker(clean_scene, Site::A);
  const std::vector<TrackerFrame> clean = all_frames(clean_tracker);
  TrackerEffects effects;
  effects.latency = TrackerLatency{60.0};  // three frames
  SimulatedHandTracker late_tracker = make_simulated_tracker(clap_with(effects), Site::A);
  const std::vector<TrackerFrame> late = all_frames(late_tracker);
  REQUIRE(late.size() == clean.size());
  int compared = 0;
  for (size_t i = 3; i < late.size(); ++i) {
    CHECK(late[i].timestamp_us == clean[i].timestamp_us);  // stamps stay on the 50 Hz grid
    const TrackerHand* now = find_hand(late[i], false);
    const TrackerHand* before = find_hand(clean[i - 3], false);
    REQUIRE(bool(now) == bool(before));
    if (!now) continue;
    CHECK((now->palm_position - before->palm_position).norm() < 0.01);
    CHECK((now->digits[1].tip - before->digits[1].tip).norm() < 0.01);
    ++compared;
  }
  CHECK(compared > 50);

  // A delay off the frame grid: compare with the motion itself.
  effects.latency = TrackerLatency{33.0};
  const Scene scene = clap_with(effects);
  const SiteSetup& setup = scene.at(Site::A);
  const MotionTrack track(setup.motion, setup.site.seat, setup.user);
  SimulatedHandTracker tracker = make_simulated_tracker(scene, Site::A);
  compared = 0;
  double moved = 0;
  while (const std::optional<TrackerFrame> frame = tracker.next_frame()) {
    const double t = frame->timestamp_us * 1e-6;
    for (const HandSkeleton& hand : skeletons_in_site(*frame, setup.site.tracker)) {
      CHECK(worst_joint_error(hand, track.pose_at(t - 0.033).right_hand) < 1e-5);
      moved = std::max(moved, (track.pose_at(t).right_hand.palm - hand.palm).norm());
      ++compared;
    }
  }
  CHECK(compared > 50);
  CHECK(moved > 0.01);  // and the delay is visible while the hand moves
}

TEST_CASE("tracker_dropouts: the lost fraction and burst length are the configured ones", "[sim][tracker]") {
  for (const TrackerDropouts config : {TrackerDropouts{0.05, 5.0}, TrackerDropouts{0.2, 2.0}, TrackerDropouts{0.1, 1.0}}) {
    INFO("probability " << config.probability << ", mean length " << config.mean_length_frames);
    std::seed_seq seed{42u};
    DropoutProcess process(config, seed);
    constexpr int kFrames = 200'000;
    int lost = 0, bursts = 0;
    bool previous = false;
    for (int i = 0; i < kFrames; ++i) {
      const bool now = process.next_frame_lost();
      lost += now;
      bursts += now && !previous;
      previous = now;
    }
    // Tolerances: 5% relative; the standard error of these estimates is under 2% at this count.
    CHECK(double(lost) / kFrames == Approx(config.probability).epsilon(0.05));
    CHECK(double(lost) / bursts == Approx(config.mean_length_frames).epsilon(0.05));
  }

  // Through the tracker: a hand always in view, frames without it at the configured rate, and
  // a new hand id after each loss, as Leap gives.
  const TrackerPlacement placement = load_scene(kScenesSimTracker / "clap.json").at(Site::A).site.tracker;
  TrackerEffects effects;
  effects.dropouts = TrackerDropouts{0.1, 4.0};
  SimulatedHandTracker tracker(steady_hand(placement), placement, effects, 7, 20'000);
  int empty = 0, reacquired = 0;
  std::optional<int32_t> last_id;
  bool last_lost = false;
  while (const std::optional<TrackerFrame> frame = tracker.next_frame()) {
    if (frame->hands.empty()) {
      ++empty;
      last_lost = true;
      continue;
    }
    if (last_id && last_lost) {
      CHECK(frame->hands[0].id != *last_id);
      ++reacquired;
    } else if (last_id) {
      CHECK(frame->hands[0].id == *last_id);
    }
    last_id = frame->hands[0].id;
    last_lost = false;
  }
  // 10% tolerance: with bursts of 4 frames the standard error at 20,000 frames is about 4% of the rate.
  CHECK(empty / 20'000.0 == Approx(0.1).epsilon(0.1));
  CHECK(reacquired > 300);
}

TEST_CASE("tracking is lost outside the tracker's range", "[sim][tracker]") {
  const TrackerPlacement placement = load_scene(kScenesSimTracker / "clap.json").at(Site::A).site.tracker;
  const Eigen::Isometry3d& site_from_tracker = placement.site_from_tracker;
  const Eigen::Vector3d device = site_from_tracker.translation();
  const Eigen::Vector3d up = site_from_tracker.linear().col(1);
  // The hand moves away from the device along its axis, from 0.02 m to 1.2 m over 100 frames.
  auto distance_at = [](double t_s) { return 0.02 + 1.18 * t_s / 2.0; };
  HandSource receding = [&](double t_s) {
    const Eigen::Vector3d palm = device + distance_at(t_s) * up;
    return std::vector<SyntheticHand>{{test::flat_hand(palm.x(), palm.y(), palm.z()), 0.085}};
  };
  SimulatedHandTracker tracker(receding, placement, {}, 1, 100);
  int seen = 0;
  while (const std::optional<TrackerFrame> frame = tracker.next_frame()) {
    const double distance = distance_at(frame->timestamp_us * 1e-6);
    const bool in_range = distance >= placement.range.min_distance_m && distance <= placement.range.max_distance_m;
    INFO("distance " << distance);
    CHECK(frame->hands.size() == (in_range ? 1u : 0u));
    seen += !frame->hands.empty();
  }
  CHECK(seen > 30);

  // Off to the side of the field of view at a good distance: not tracked either.
  const Eigen::Vector3d side = site_from_tracker.linear().col(0);
  HandSource aside = [&](double) {
    const Eigen::Vector3d palm = device + 0.1 * up + 0.4 * side;  // 76 degrees off the axis
    return std::vector<SyntheticHand>{{test::flat_hand(palm.x(), palm.y(), palm.z()), 0.085}};
  };
  SimulatedHandTracker aside_tracker(aside, placement, {}, 1, 10);
  while (const std::optional<TrackerFrame> frame = aside_tracker.next_frame()) CHECK(frame->hands.empty());
}

TEST_CASE("the simulated tracker is deterministic from the scene's seed", "[sim][tracker]") {
  const Scene noisy = load_scene(kScenesSimTracker / "noisy-clap.json");
  SimulatedHandTracker first = make_simulated_tracker(noisy, Site::B);
  SimulatedHandTracker second = make_simulated_tracker(noisy, Site::B);
  const std::vector<TrackerFrame> a = all_frames(first), b = all_frames(second);
  CHECK(a == b);
  Scene reseeded = noisy;
  reseeded.seed += 1;
  SimulatedHandTracker third = make_simulated_tracker(reseeded, Site::B);
  CHECK(all_frames(third) != a);
  // The two sites draw from different streams: the same user and motion at both gives
  // different noise.
  Scene twins = noisy;
  twins.sites[1] = twins.sites[0];
  SimulatedHandTracker at_a = make_simulated_tracker(twins, Site::A);
  SimulatedHandTracker at_b = make_simulated_tracker(twins, Site::B);
  const std::vector<TrackerFrame> frames_a = all_frames(at_a), frames_b = all_frames(at_b);
  REQUIRE(frames_a.size() == frames_b.size());
  int both_tracked = 0, different = 0;
  for (size_t i = 0; i < frames_a.size(); ++i)
    if (!frames_a[i].hands.empty() && !frames_b[i].hands.empty()) {
      ++both_tracked;
      different += frames_a[i].hands[0].palm_position != frames_b[i].hands[0].palm_position;
    }
  CHECK(both_tracked > 50);
  CHECK(different == both_tracked);
}
