// The simulated users' motions: smooth, the hands never pass through the screen, the arms keep
// their lengths, and a touch lands flat on the glass at the spot the scene asks for.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

#include "config/json.h"
#include "sim/hand_model.h"
#include "sim/motion.h"
#include "sim/person.h"

using namespace rt;
using namespace rt::sim;
using Catch::Matchers::Contains;

namespace {

std::vector<Eigen::Vector3d> all_joints(const PersonPose& pose) {
  std::vector<Eigen::Vector3d> joints = pose.right_hand.hand_joints();
  const std::vector<Eigen::Vector3d> left = pose.left_hand.hand_joints();
  joints.insert(joints.end(), left.begin(), left.end());
  for (const ArmPose* arm : {&pose.right_arm, &pose.left_arm}) {
    joints.push_back(arm->shoulder);
    joints.push_back(arm->elbow);
  }
  joints.push_back(pose.head_centre);
  joints.push_back(pose.neck_base);
  return joints;
}

UserAppearance with_hand_scale(double scale) {
  UserAppearance user;
  user.hand_scale = scale;
  return user;
}

MotionSpec motion(MotionKind kind, Eigen::Vector2d target = {0.08, 0.05}) {
  MotionSpec spec;
  spec.kind = kind;
  spec.touch_target_m = target;
  spec.hold_s = 0.5;
  return spec;
}

// Palm-side joints of a hand: what lies flat on the glass at a touch.
std::vector<Eigen::Vector3d> palm_joints(const HandSkeleton& hand) {
  std::vector<Eigen::Vector3d> joints{hand.wrist, hand.palm};
  for (int d = 0; d < kDigitCount; ++d) {
    joints.push_back(hand.joint(Digit(d), DigitJoint::Carp));
    joints.push_back(hand.joint(Digit(d), DigitJoint::Mcp));
  }
  return joints;
}

}  // namespace

TEST_CASE("every motion is smooth, stays in front of the glass and keeps the arms whole", "[sim][motion]") {
  const Seat seat;
  // Joint speed and acceleration bounds of a brisk human reach (a fast reach peaks near 2 m/s).
  constexpr double kMaxSpeed = 3.0;          // m/s
  constexpr double kMaxAcceleration = 60.0;  // m/s^2
  constexpr double kStep = 0.002;            // s: fine enough to see a jump of a few millimetres
  for (MotionKind kind : all_motion_kinds())
    for (double scale : {0.8, 1.0, 1.2}) {
      INFO(motion_name(kind) << ", hand scale " << scale);
      const MotionTrack track(motion(kind), seat, with_hand_scale(scale));
      const BodyGeometry& body = track.body();
      REQUIRE(track.duration_s() > 0.5);
      double max_speed = 0, max_acceleration = 0, min_z = 1e9, max_forearm_error = 0;
      std::vector<Eigen::Vector3d> previous, before_previous;
      for (double t = -0.1; t <= track.duration_s() + 0.2; t += kStep) {
        const PersonPose pose = track.pose_at(t);
        const std::vector<Eigen::Vector3d> joints = all_joints(pose);
        for (size_t i = 0; i < joints.size(); ++i) {
          REQUIRE(joints[i].allFinite());
          min_z = std::min(min_z, joints[i].z());
          if (!previous.empty()) max_speed = std::max(max_speed, (joints[i] - previous[i]).norm() / kStep);
          if (!before_previous.empty())
            max_acceleration = std::max(
                max_acceleration, (joints[i] - 2 * previous[i] + before_previous[i]).norm() / (kStep * kStep));
        }
        for (const ArmPose* arm : {&pose.right_arm, &pose.left_arm}) {
          REQUIRE((arm->elbow - arm->shoulder).norm() == Approx(body.upper_arm_m).margin(1e-9));
          max_forearm_error = std::max(max_forearm_error, std::abs((arm->wrist - arm->elbow).norm() - body.forearm_m));
        }
        REQUIRE((pose.right_arm.wrist - pose.right_hand.wrist).norm() < 1e-12);
        REQUIRE((pose.left_arm.wrist - pose.left_hand.wrist).norm() < 1e-12);
        REQUIRE((pose.right_hand.elbow - pose.right_arm.elbow).norm() < 1e-12);
        before_previous = std::move(previous);
        previous = joints;
      }
      CHECK(min_z >= 0.0);  // nothing passes through the screen
      CHECK(max_speed < kMaxSpeed);
      CHECK(max_speed > 0.0);  // every motion moves (idle breathes)
      CHECK(max_acceleration < kMaxAcceleration);
      CHECK(max_forearm_error < 1e-3);  // every wrist within reach: the forearm keeps its length
    }
}

TEST_CASE("the hand stays in front of the glass at 30 fps too, for every touch spot in reach", "[sim][motion]") {
  const Seat seat;
  for (MotionKind kind : all_motion_kinds())
    for (const Eigen::Vector2d& target : {Eigen::Vector2d(0.0, 0.0), Eigen::Vector2d(0.25, -0.15), Eigen::Vector2d(-0.05, 0.0)}) {
      const MotionTrack track(motion(kind, target), seat, with_hand_scale(0.85));
      for (int frame = 0; frame < int(track.duration_s() * 30) + 2; ++frame) {
        const PersonPose pose = track.pose_at(frame / 30.0);
        for (const HandSkeleton* hand : {&pose.right_hand, &pose.left_hand})
          for (const Eigen::Vector3d& joint : hand->hand_joints()) {
            INFO(motion_name(kind) << " frame " << frame << " joint " << joint.transpose());
            REQUIRE(joint.z() >= 0.0);
          }
      }
    }
}

TEST_CASE("clap presses the palm flat on the glass at the configured spot and holds it", "[sim][motion]") {
  const Seat seat;
  for (const Eigen::Vector2d& target : {Eigen::Vector2d(0.08, 0.05), Eigen::Vector2d(-0.1, 0.0), Eigen::Vector2d(0.25, -0.1)})
    for (double scale : {0.85, 1.1}) {
      INFO("target " << target.transpose() << ", hand scale " << scale);
      MotionSpec spec = motion(MotionKind::Clap, target);
      spec.hold_s = 0.8;
      const MotionTrack track(spec, seat, with_hand_scale(scale));
      double min_palm_z = 1e9, touching_s = 0;
      PersonPose at_touch;
      for (int frame = 0; frame <= int(track.duration_s() * 30); ++frame) {
        const PersonPose pose = track.pose_at(frame / 30.0);
        if (pose.right_hand.palm.z() < min_palm_z) {
          min_palm_z = pose.right_hand.palm.z();
          at_touch = pose;
        }
        if (pose.right_hand.palm.z() < 0.01) touching_s += 1.0 / 30;
      }
      CHECK(min_palm_z < 0.01);
      CHECK(min_palm_z == Approx(kTouchPalmHeightM).margin(1e-6));
      CHECK((at_touch.right_hand.palm.head<2>() - target).norm() < 1e-6);
      for (const Eigen::Vector3d& joint : palm_joints(at_touch.right_hand)) CHECK(joint.z() == Approx(0.005).margin(1e-6));
      for (const Eigen::Vector3d& joint : at_touch.right_hand.hand_joints()) CHECK(joint.z() < 0.01);  // flat
      CHECK(at_touch.right_hand.palm_normal.z() == Approx(-1.0));  // facing the screen
      CHECK(touching_s >= spec.hold_s);
      CHECK(touching_s < spec.hold_s + 0.5);
      // It starts and ends at rest, hands on the thighs, far from the glass.
      CHECK(track.pose_at(0).right_hand.palm.z() > 0.4);
      CHECK(track.pose_at(track.duration_s()).right_hand.palm.z() > 0.4);
    }
}

TEST_CASE("clap is raise, approach, touch_hold and retract in a row", "[sim][motion]") {
  const Seat seat;
  const UserAppearance user;
  const MotionTrack clap(motion(MotionKind::Clap), seat, user);
  const MotionTrack raise(motion(MotionKind::Raise), seat, user);
  const MotionTrack approach(motion(MotionKind::Approach), seat, user);
  const MotionTrack touch(motion(MotionKind::TouchHold), seat, user);
  const MotionTrack retract(motion(MotionKind::Retract), seat, user);
  auto same_hand = [](const PersonPose& a, const PersonPose& b) {
    const auto ja = a.right_hand.hand_joints(), jb = b.right_hand.hand_joints();
    double worst = 0;
    for (size_t i = 0; i < ja.size(); ++i) worst = std::max(worst, (ja[i] - jb[i]).norm());
    return worst;
  };
  double t = 0;
  for (const MotionTrack* part : {&raise, &approach, &touch, &retract}) {
    // Each part starts where the previous one ended, and clap passes through the same poses.
    CHECK(same_hand(clap.pose_at(t), part->pose_at(0)) < 1e-9);
    CHECK(same_hand(clap.pose_at(t + 0.5 * part->duration_s()), part->pose_at(0.5 * part->duration_s())) < 0.01);
    t += part->duration_s();
  }
  CHECK(t == Approx(clap.duration_s()));
}

TEST_CASE("wave holds the hand in front of the chest, between the cameras and the body", "[sim][motion]") {
  const Seat seat;
  const MotionTrack track(motion(MotionKind::Wave), seat, UserAppearance{});
  double lateral_min = 1e9, lateral_max = -1e9;
  int in_front_frames = 0;
  for (int frame = 0; frame <= int(track.duration_s() * 30); ++frame) {
    const PersonPose pose = track.pose_at(frame / 30.0);
    const Eigen::Vector3d palm = pose.right_hand.palm;
    const double chest_front_z = pose.neck_base.z() - pose.torso_depth_m / 2;
    const bool over_torso = std::abs(palm.x()) < pose.shoulder_width_m / 2 && palm.y() < pose.neck_base.y() &&
                            palm.y() > pose.pelvis.y();
    if (over_torso && palm.z() < chest_front_z - 0.1) {
      ++in_front_frames;
      lateral_min = std::min(lateral_min, palm.x());
      lateral_max = std::max(lateral_max, palm.x());
    }
  }
  CHECK(in_front_frames > 40);                   // over a second in front of the chest
  CHECK(lateral_max - lateral_min > 0.12);       // and it waves from side to side
}

TEST_CASE("the hand model: a medium adult hand, scaled; thumb metacarpal of zero length; left mirrors right",
          "[sim][motion]") {
  CHECK(medium_hand_length_m() == Approx(0.18).margin(0.01));
  HandPlacement placement;
  placement.palm = {0.1, 0.0, 0.2};
  placement.orientation = hand_orientation(Eigen::Vector3d::UnitY(), -Eigen::Vector3d::UnitZ());
  for (double scale : {0.8, 1.0, 1.25}) {
    const HandSkeleton hand = build_hand(placement, false, scale);
    CHECK(hand.joint(Digit::Thumb, DigitJoint::Carp) == hand.joint(Digit::Thumb, DigitJoint::Mcp));
    for (int d = 0; d < kDigitCount; ++d) {
      const DigitModel& model = medium_adult_hand()[d];
      for (int bone = 0; bone < 3; ++bone)
        CHECK((hand.digits[d][bone + 2] - hand.digits[d][bone + 1]).norm() ==
              Approx(scale * model.phalanges_m[bone]).epsilon(1e-9));
    }
    const double length = (hand.joint(Digit::Middle, DigitJoint::Tip) - hand.wrist).norm();
    CHECK(length == Approx(scale * medium_hand_length_m()).epsilon(1e-9));
    CHECK(palm_width_m(scale) == Approx(0.085 * scale));
  }
  // Palm to the screen, fingers up: the right thumb is on the user's left (-x), the left
  // hand's on the right; otherwise the hands are mirror images across the palm centre.
  const HandSkeleton right = build_hand(placement, false, 1.0);
  const HandSkeleton left = build_hand(placement, true, 1.0);
  CHECK(right.joint(Digit::Thumb, DigitJoint::Tip).x() < right.palm.x() - 0.03);
  CHECK(left.joint(Digit::Thumb, DigitJoint::Tip).x() > left.palm.x() + 0.03);
  const Eigen::Vector3d mirror(-1, 1, 1);
  for (int d = 0; d < kDigitCount; ++d)
    for (int j = 0; j < kJointsPerDigit; ++j)
      CHECK(((left.digits[d][j] - left.palm) - mirror.cwiseProduct(right.digits[d][j] - right.palm)).norm() < 1e-12);
  CHECK(left.is_left);
  CHECK_FALSE(right.is_left);
  // Curling bends the fingers towards the palm side.
  placement.curl = 1.0;
  const HandSkeleton fist = build_hand(placement, false, 1.0);
  CHECK(fist.joint(Digit::Index, DigitJoint::Tip).z() < placement.palm.z() - 0.03);
}

TEST_CASE("start delay, speed and the pose before the start and after the end", "[sim][motion]") {
  const Seat seat;
  const UserAppearance user;
  MotionSpec spec = motion(MotionKind::Raise);
  const MotionTrack nominal(spec, seat, user);
  spec.start_delay_s = 1.0;
  spec.speed = 2.0;
  const MotionTrack delayed(spec, seat, user);
  CHECK(delayed.duration_s() == Approx(1.0 + nominal.duration_s() / 2));
  const PersonPose rest = nominal.pose_at(0.0);
  CHECK((delayed.pose_at(0.9).right_hand.palm - rest.right_hand.palm).norm() < 1e-12);
  CHECK((delayed.pose_at(1.0 + nominal.duration_s() / 4).right_hand.palm -
         nominal.pose_at(nominal.duration_s() / 2).right_hand.palm).norm() < 1e-12);
  CHECK((nominal.pose_at(-5.0).right_hand.palm - rest.right_hand.palm).norm() < 1e-12);
  CHECK((nominal.pose_at(100.0).right_hand.palm - nominal.pose_at(nominal.duration_s()).right_hand.palm).norm() < 1e-12);
  CHECK(nominal.pose_at(1.5).right_hand.timestamp_us == 1'500'000);
  CHECK((evaluate_motion(spec, seat, user, 1.2).right_hand.palm - delayed.pose_at(1.2).right_hand.palm).norm() == 0.0);
  CHECK_THROWS_AS(nominal.pose_at(std::nan("")), std::invalid_argument);
}

TEST_CASE("a repeating motion starts again from its first pose; a period shorter than the motion is refused",
          "[sim][motion]") {
  const Seat seat;
  const UserAppearance user;
  MotionSpec spec = motion(MotionKind::Clap, {0.02, 0.0});
  const MotionTrack once(spec, seat, user);
  spec.repeat_every_s = once.duration_s() + 0.5;
  const MotionTrack repeating(spec, seat, user);
  for (double t : {0.0, 0.3, once.duration_s() * 0.5, once.duration_s() - 0.01})
    for (int cycle : {1, 3}) {
      const double later = t + cycle * spec.repeat_every_s;
      CHECK((repeating.pose_at(later).right_hand.palm - once.pose_at(t).right_hand.palm).norm() < 1e-9);
      CHECK(repeating.pose_at(later).right_hand.timestamp_us == uint64_t(std::llround(later * 1e6)));
    }
  // Between the end and the next start, the last pose holds, as a single play does.
  CHECK((repeating.pose_at(once.duration_s() + 0.25).right_hand.palm - once.pose_at(once.duration_s()).right_hand.palm)
            .norm() < 1e-9);
  spec.repeat_every_s = once.duration_s() * 0.5;
  CHECK_THROWS_WITH(MotionTrack(spec, seat, user), Contains("repeat_every_s") && Contains("shorter than the motion"));
  CHECK(motion_from_json({{"name", "clap"}, {"repeat_every_s", 8.0}}, "m").repeat_every_s == 8.0);
  CHECK_THROWS_WITH(motion_from_json({{"name", "clap"}, {"repeat_every_s", -1.0}}, "m"), Contains("'repeat_every_s'"));
}

TEST_CASE("a touch target out of the arm's reach is refused", "[sim][motion]") {
  const Seat seat;
  CHECK_THROWS_WITH(MotionTrack(motion(MotionKind::Clap, {-0.7, 0.4}), seat, with_hand_scale(0.8)),
                    Contains("out of reach") && Contains("-0.7"));
  // An idle user never reaches for the glass, so the target does not matter.
  CHECK_NOTHROW(MotionTrack(motion(MotionKind::Idle, {-0.7, 0.4}), seat, with_hand_scale(0.8)));
}

TEST_CASE("motions from JSON", "[sim][motion]") {
  const MotionSpec spec = motion_from_json(
      {{"name", "touch_hold"}, {"touch_target_m", {0.1, -0.05}}, {"hold_s", 2.0}, {"speed", 1.5}}, "motion");
  CHECK(spec.kind == MotionKind::TouchHold);
  CHECK(spec.touch_target_m == Eigen::Vector2d(0.1, -0.05));
  CHECK(spec.hold_s == 2.0);
  CHECK(spec.speed == 1.5);
  CHECK(motion_from_json(motion_to_json(spec), "again").touch_target_m == spec.touch_target_m);
  for (MotionKind kind : all_motion_kinds()) CHECK(motion_kind_from_name(motion_name(kind)) == kind);

  CHECK_THROWS_WITH(motion_from_json({{"name", "moonwalk"}}, "site A motion"),
                    Contains("site A motion") && Contains("unknown motion 'moonwalk'") && Contains("fast_approach"));
  CHECK_THROWS_WITH(motion_from_json({{"touch_target_m", {0, 0}}}, "m"), Contains("missing field 'name'"));
  CHECK_THROWS_WITH(motion_from_json({{"name", "clap"}, {"touch_target_m", {0.1}}}, "m"), Contains("'touch_target_m'"));
  CHECK_THROWS_WITH(motion_from_json({{"name", "clap"}, {"speed", 0.0}}, "m"), Contains("'speed'"));
  CHECK_THROWS_WITH(motion_from_json({{"name", "clap"}, {"hold", 1.0}}, "m"), Contains("unknown field 'hold'"));
  CHECK_THROWS_WITH(motion_from_json({{"name", 3}}, "m"), Contains("'name' must be a string"));
}
