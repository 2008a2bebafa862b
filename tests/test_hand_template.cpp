// The hand template asset, bone frames and shape adaption (CPU): the committed glTF files load
// with the promised invariants and match the generator; posing is robust to the hard cases;
// a skeleton scaled by a known factor gives the analytically expected vertices.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>

#include "hand/hand_bones.h"
#include "hand/hand_template.h"
#include "hand/shape_adaption.h"
#include "passes/hand_skinning.h"
#include "sim/hand_model.h"

using namespace rt;
using namespace rt::hand;

namespace {

const std::filesystem::path kAssets = std::filesystem::path(REMOTETOUCH_ASSETS_DIR) / "hand";

HandSkeleton posed_hand(bool is_left, double scale, double curl, const Eigen::Vector3d& palm,
                        const Eigen::Quaterniond& orientation = Eigen::Quaterniond::Identity()) {
  sim::HandPlacement placement;
  placement.palm = palm;
  placement.orientation = orientation;
  placement.curl = curl;
  HandSkeleton hand = sim::build_hand(placement, is_left, scale);
  hand.elbow = hand.wrist - 0.25 * scale * hand.direction;
  return hand;
}

std::vector<Eigen::Vector3d> skin(const BoneFrames& frames, const RestSkeleton& rest, std::span<const HandVertex> vertices) {
  const auto skinned = passes::hand_skinning_reference(vertices, skinning_matrices(frames, rest));
  std::vector<Eigen::Vector3d> out;
  for (const auto& v : skinned) out.emplace_back(v.position_u[0], v.position_u[1], v.position_u[2]);
  return out;
}

bool all_finite(const std::vector<Eigen::Vector3d>& points) {
  for (const auto& p : points)
    if (!p.allFinite()) return false;
  return true;
}

}  // namespace

TEST_CASE("The committed hand templates load with the promised invariants") {
  for (bool is_left : {false, true}) {
    const HandTemplate hand = load_hand_template(kAssets, is_left);
    INFO((is_left ? "left" : "right"));
    CHECK(hand.is_left == is_left);
    CHECK(hand.vertices.size() >= 3000);
    CHECK(hand.texture.width >= 64);
    // At most four influences with weights summing to one (validate_hand_template checks per
    // vertex; here the thumb's zero-length metacarpal, which can carry no shape, has no weight).
    for (const auto& v : hand.vertices)
      for (int k = 0; k < 4; ++k)
        if (v.weights[k] > 0) CHECK(int(v.joints[k]) != digit_bone(0, 0));
    CHECK(hand.rest[digit_bone(0, 0)].length_m == Approx(0.0).margin(1e-9));
    // The committed files are what the generator writes (regenerate_hand_template).
    const HandTemplate generated = build_hand_template(is_left);
    REQUIRE(generated.vertices.size() == hand.vertices.size());
    REQUIRE(generated.indices == hand.indices);
    double worst = 0;
    for (size_t i = 0; i < hand.vertices.size(); ++i)
      for (int c = 0; c < 4; ++c) worst = std::max(worst, double(std::abs(hand.vertices[i].position_u[c] - generated.vertices[i].position_u[c])));
    CHECK(worst < 1e-6);
    for (int bone = 0; bone < kBoneCount; ++bone)
      CHECK((hand.rest[bone].frame.matrix() - generated.rest[bone].frame.matrix()).norm() < 1e-5);
  }
  // Both hands together stay small.
  uintmax_t bytes = 0;
  for (const auto& entry : std::filesystem::directory_iterator(kAssets)) bytes += entry.file_size();
  CHECK(bytes < 700 * 1024);
}

TEST_CASE("The rest shape: the generator's flat medium hand, bones and mesh") {
  // The skeleton definition (sim/hand_model.h) read here directly, in the template's frame:
  // wrist at the origin, fingers along +y, palm towards +z, the right hand's thumb at +x.
  constexpr double kRadiansPerDegree = 3.14159265358979323846 / 180.0;
  constexpr double kForearmM = 0.25;  // the generator's forearm
  const Eigen::Vector3d palm_out = Eigen::Vector3d::UnitZ();
  for (bool is_left : {false, true})
    for (bool committed : {true, false}) {
      const HandTemplate hand = committed ? load_hand_template(kAssets, is_left) : build_hand_template(is_left);
      INFO((is_left ? "left" : "right") << (committed ? ", committed" : ", generated"));
      const double mirror = is_left ? -1.0 : 1.0;
      auto at = [&](const Eigen::Vector2d& uv) { return Eigen::Vector3d(mirror * uv.x(), uv.y(), 0.0); };
      // Bone starts, ends and directions as the definition gives them.
      std::array<Eigen::Vector3d, kBoneCount> start, end;
      start[kArmBone] = Eigen::Vector3d(0, -kForearmM, 0);
      end[kArmBone] = Eigen::Vector3d::Zero();
      start[kWristBone] = Eigen::Vector3d::Zero();
      end[kWristBone] = at(sim::medium_adult_hand()[int(Digit::Middle)].mcp_uv);
      for (int d = 0; d < kDigitCount; ++d) {
        const sim::DigitModel& model = sim::medium_adult_hand()[d];
        const double splay = model.splay_deg * kRadiansPerDegree;
        const Eigen::Vector3d straight(mirror * std::sin(splay), std::cos(splay), 0.0);
        start[digit_bone(d, 0)] = at(model.carp_uv);
        end[digit_bone(d, 0)] = at(model.mcp_uv);
        Eigen::Vector3d joint = at(model.mcp_uv);
        for (int b = 1; b < kBonesPerDigit; ++b) {
          start[digit_bone(d, b)] = joint;
          joint += model.phalanges_m[size_t(b - 1)] * straight;
          end[digit_bone(d, b)] = joint;
        }
      }
      for (int bone = 0; bone < kBoneCount; ++bone) {
        INFO("bone " << bone_name(bone));
        const BoneRest& rest = hand.rest[bone];
        CHECK((rest.frame.translation() - start[bone]).norm() < 1e-6);
        CHECK(rest.length_m == Approx((end[bone] - start[bone]).norm()).margin(1e-6));
        // +y along the bone (the thumb's zero-length metacarpal: along its proximal bone; the
        // wrist bone: along the hand's direction, +y, not quite towards the middle knuckle), +z out
        // of the palm: the flat hand's bones all lie in its plane.
        const int along_bone = bone == digit_bone(0, 0) ? digit_bone(0, 1) : bone;
        const Eigen::Vector3d along = bone == kWristBone ? Eigen::Vector3d::UnitY()
                                                         : Eigen::Vector3d((end[along_bone] - start[along_bone]).normalized());
        CHECK((rest.frame.linear().col(1) - along).norm() < 1e-6);
        CHECK((rest.frame.linear().col(2) - palm_out).norm() < 1e-6);
        CHECK(std::abs(rest.frame.linear().determinant() - 1.0) < 1e-9);
      }
      // This reading of the definition gives its own hand length (wrist to middle fingertip).
      CHECK((end[digit_bone(2, 3)] - start[kWristBone]).norm() == Approx(sim::medium_hand_length_m()).epsilon(1e-12));

      // The mesh in its bind pose lies on these bones: each vertex within a finger's or the palm's
      // thickness of the bone that weighs most on it, and each finger ends just past its tip joint.
      auto distance_to_bone = [&](const Eigen::Vector3d& p, int bone) {
        const Eigen::Vector3d a = start[bone], ab = end[bone] - start[bone];
        const double t = ab.squaredNorm() > 0 ? std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0) : 0.0;
        return (p - (a + t * ab)).norm();
      };
      std::array<double, kBoneCount> worst_by_bone{};
      std::array<double, kDigitCount> reach{};
      reach.fill(-1.0);
      for (const HandVertex& v : hand.vertices) {
        const Eigen::Vector3d p(v.position_u[0], v.position_u[1], v.position_u[2]);
        int heaviest = 0;
        for (int k = 1; k < 4; ++k)
          if (v.weights[k] > v.weights[heaviest]) heaviest = k;
        const int bone = int(v.joints[heaviest]);
        REQUIRE(bone >= 0);
        REQUIRE(bone < kBoneCount);
        worst_by_bone[size_t(bone)] = std::max(worst_by_bone[size_t(bone)], distance_to_bone(p, bone));
        for (int d = 0; d < kDigitCount; ++d)
          if (bone == digit_bone(d, 3)) {
            const Eigen::Vector3d along = (end[bone] - start[bone]).normalized();
            reach[size_t(d)] = std::max(reach[size_t(d)], (p - end[bone]).dot(along));
          }
      }
      // A finger's tube is at most 13 mm thick (the thumb's), the forearm 29 mm; the wrist bone
      // carries the palm (4.5 cm either side of it at the knuckles) and the thumb's base.
      for (int bone = 0; bone < kBoneCount; ++bone) {
        INFO("bone " << bone_name(bone));
        CHECK(worst_by_bone[size_t(bone)] < (bone == kWristBone ? 0.055 : bone == kArmBone ? 0.030 : 0.014));
      }
      for (int d = 0; d < kDigitCount; ++d) {
        INFO("digit " << d << " reaches " << reach[size_t(d)] * 1000 << " mm past its tip joint");
        CHECK(reach[size_t(d)] > 0.002);  // the fingertip's cap: 5 to 8 mm
        CHECK(reach[size_t(d)] < 0.010);
      }
    }
}

TEST_CASE("Bad template files give an error that names the file and the problem") {
  const auto dir = std::filesystem::temp_directory_path() / "rt_bad_hand_template";
  std::filesystem::create_directories(dir);
  CHECK_THROWS_WITH(load_hand_template(dir / "nothing.gltf"), Catch::Contains("no such file"));
  std::ofstream(dir / "right_hand.gltf") << "{ not json";
  CHECK_THROWS_WITH(load_hand_template(dir, false), Catch::Contains("right_hand.gltf") && Catch::Contains("glTF"));
  // A template whose .bin is cut short.
  std::filesystem::copy_file(kAssets / "left_hand.gltf", dir / "left_hand.gltf", std::filesystem::copy_options::overwrite_existing);
  std::filesystem::copy_file(kAssets / "hand_skin.png", dir / "hand_skin.png", std::filesystem::copy_options::overwrite_existing);
  {
    std::ifstream in(kAssets / "left_hand.bin", std::ios::binary);
    std::vector<char> bytes((std::istreambuf_iterator<char>(in)), {});
    std::ofstream(dir / "left_hand.bin", std::ios::binary).write(bytes.data(), std::streamsize(bytes.size() / 2));
  }
  CHECK_THROWS_AS(load_hand_template(dir, true), HandTemplateError);
}

TEST_CASE("Posing the rest skeleton gives identity skinning; rigid motions move the mesh rigidly") {
  const HandTemplate hand = build_hand_template(false);
  HandSkeleton rest = posed_hand(false, 1.0, 0.0, Eigen::Vector3d(0, sim::palm_centre_uv().y(), 0));
  const BonePose pose = pose_bones(rest, hand.rest);
  REQUIRE(pose.ok());
  for (int bone = 0; bone < kBoneCount; ++bone)
    CHECK((skinning_transform(pose.frames[bone], hand.rest[bone]) - Eigen::Matrix4d::Identity()).norm() < 1e-9);

  const Eigen::Quaterniond turn(Eigen::AngleAxisd(0.7, Eigen::Vector3d(0.3, -1, 0.5).normalized()));
  const Eigen::Vector3d where(0.1, -0.2, 0.35);
  HandSkeleton moved = posed_hand(false, 1.0, 0.0, where, turn);
  const BonePose moved_pose = pose_bones(moved, hand.rest);
  REQUIRE(moved_pose.ok());
  const auto skinned = skin(moved_pose.frames, hand.rest, hand.vertices);
  const Eigen::Vector3d rest_palm(0, sim::palm_centre_uv().y(), 0);
  double worst = 0;
  for (size_t i = 0; i < skinned.size(); ++i) {
    const Eigen::Vector3d p(hand.vertices[i].position_u[0], hand.vertices[i].position_u[1], hand.vertices[i].position_u[2]);
    worst = std::max(worst, (skinned[i] - (where + turn * (p - rest_palm))).norm());
  }
  CHECK(worst < 1e-5);
}

TEST_CASE("Hard skeletons: zero-length thumb metacarpal, collinear joints, missing joints, degenerate hands") {
  const HandTemplate hand = build_hand_template(true);
  const Eigen::Vector3d palm(0.05, 0.0, 0.3);

  SECTION("a curled hand, whose thumb metacarpal has zero length, poses every bone") {
    const HandSkeleton curled = posed_hand(true, 1.0, 0.8, palm);
    REQUIRE((curled.joint(Digit::Thumb, DigitJoint::Carp) - curled.joint(Digit::Thumb, DigitJoint::Mcp)).norm() < 1e-12);
    const BonePose pose = pose_bones(curled, hand.rest);
    REQUIRE(pose.ok());
    CHECK(pose.fallback_bones == 0);
    // Flexion keeps bone lengths, so each posed joint is the tracked one (template scale 1).
    for (int d = 0; d < kDigitCount; ++d)
      CHECK((posed_tip(pose.frames, hand.rest, d) - curled.digits[d][4]).norm() < 1e-9);
  }
  SECTION("a flat hand has collinear finger joints and still gets proper rotations") {
    const BonePose pose = pose_bones(posed_hand(true, 1.0, 0.0, palm), hand.rest);
    REQUIRE(pose.ok());
    for (const auto& frame : pose.frames) CHECK(std::abs(frame.linear().determinant() - 1.0) < 1e-9);
  }
  SECTION("missing finger joints hold the rest pose relative to the parent, never NaN") {
    HandSkeleton hand_with_gaps = posed_hand(true, 1.0, 0.5, palm);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    hand_with_gaps.joint(Digit::Index, DigitJoint::Tip) = Eigen::Vector3d::Constant(nan);
    hand_with_gaps.joint(Digit::Ring, DigitJoint::Pip) = Eigen::Vector3d(nan, 0, 0);
    hand_with_gaps.elbow = Eigen::Vector3d::Constant(nan);
    const BonePose pose = pose_bones(hand_with_gaps, hand.rest);
    REQUIRE(pose.ok());
    CHECK(pose.fallback_bones == 3);  // index distal, ring proximal and intermediate
    CHECK(all_finite(skin(pose.frames, hand.rest, hand.vertices)));
  }
  SECTION("a skeleton collapsed to one point with a valid frame gives the rest-shaped hand there") {
    HandSkeleton point = posed_hand(true, 1.0, 0.0, palm);
    for (auto& digit : point.digits) digit.fill(point.wrist);
    const BonePose pose = pose_bones(point, hand.rest);
    REQUIRE(pose.ok());
    CHECK(pose.fallback_bones == 5 * kBonesPerDigit);  // no digit bone has a direction
    const auto skinned = skin(pose.frames, hand.rest, hand.vertices);
    REQUIRE(all_finite(skinned));
    // The hand frame is the rest one (orientation identity): every vertex is its rest position
    // moved by the wrist, the mesh unbent.
    double worst = 0;
    for (size_t i = 0; i < skinned.size(); ++i) {
      const Eigen::Vector3d rest(hand.vertices[i].position_u[0], hand.vertices[i].position_u[1], hand.vertices[i].position_u[2]);
      worst = std::max(worst, (skinned[i] - (rest + point.wrist)).norm());
    }
    CHECK(worst < 1e-6);
  }
  SECTION("no wrist, or no way to form the hand frame, is a clear error") {
    HandSkeleton no_wrist = posed_hand(true, 1.0, 0.0, palm);
    no_wrist.wrist = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
    CHECK_THAT(pose_bones(no_wrist, hand.rest).error, Catch::Contains("wrist"));
    HandSkeleton flat = posed_hand(true, 1.0, 0.0, palm);
    flat.palm_normal = flat.direction;  // parallel: no normal
    for (auto& digit : flat.digits) digit.fill(flat.wrist + 0.05 * flat.direction);  // knuckles on the axis
    CHECK_THAT(pose_bones(flat, hand.rest).error, Catch::Contains("no hand frame"));
  }
}

TEST_CASE("Shape adaption: a skeleton scaled by k gives the template scaled by k about the wrist") {
  for (bool is_left : {false, true})
    for (double k : {0.8, 1.0, 1.17}) {
      const HandTemplate hand = build_hand_template(is_left);
      const HandSkeleton scaled = posed_hand(is_left, k, 0.0, Eigen::Vector3d(0, k * sim::palm_centre_uv().y(), 0));
      const BoneScales scales = bone_scales(scaled, hand.rest);
      REQUIRE(scales.ok());
      for (double s : scales.scale) CHECK(s == Approx(k).epsilon(1e-9));
      const RestSkeleton adapted = adapted_rest_skeleton(hand.rest, scales);
      const auto vertices = adapt_rest_mesh(hand.vertices, hand.rest, adapted, scales);
      double worst = 0;
      for (size_t i = 0; i < vertices.size(); ++i)
        for (int c = 0; c < 3; ++c)  // the wrist is the origin
          worst = std::max(worst, double(std::abs(vertices[i].position_u[c] - k * hand.vertices[i].position_u[c])));
      CHECK(worst < 1e-6);
      // Posed with the adapted skeleton, the fingertips land on the scaled skeleton's tips.
      const HandSkeleton curled = posed_hand(is_left, k, 0.6, Eigen::Vector3d(0.02, 0.1, 0.3));
      const BonePose pose = pose_bones(curled, adapted);
      REQUIRE(pose.ok());
      for (int d = 0; d < kDigitCount; ++d) CHECK((posed_tip(pose.frames, adapted, d) - curled.digits[d][4]).norm() < 1e-9);
    }
}

TEST_CASE("Shape adaption per bone: longer fingers stretch only their own bones; bad input is refused") {
  const HandTemplate hand = build_hand_template(false);
  HandSkeleton long_index = posed_hand(false, 1.0, 0.0, Eigen::Vector3d(0, sim::palm_centre_uv().y(), 0));
  const Eigen::Vector3d pip = long_index.joint(Digit::Index, DigitJoint::Pip);
  const Eigen::Vector3d along = (pip - long_index.joint(Digit::Index, DigitJoint::Mcp)).normalized();
  for (int j = int(DigitJoint::Pip); j <= int(DigitJoint::Tip); ++j) long_index.digits[1][j] += 0.01 * along;
  const BoneScales scales = bone_scales(long_index, hand.rest);
  REQUIRE(scales.ok());
  CHECK(scales.scale[digit_bone(1, 1)] == Approx((hand.rest[digit_bone(1, 1)].length_m + 0.01) / hand.rest[digit_bone(1, 1)].length_m));
  CHECK(scales.scale[digit_bone(1, 2)] == Approx(1.0));
  CHECK(scales.scale[digit_bone(2, 1)] == Approx(1.0));
  // The thumb's metacarpal has no length to measure: it takes the palm's scale.
  CHECK(scales.scale[digit_bone(0, 0)] == Approx(scales.scale[kWristBone]));

  HandSkeleton broken = long_index;
  broken.joint(Digit::Middle, DigitJoint::Mcp) = Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
  CHECK_THAT(bone_scales(broken, hand.rest).error, Catch::Contains("middle knuckle"));
  HandSkeleton huge = long_index;
  for (auto& digit : huge.digits) digit[4] = digit[3] + 10.0 * (digit[4] - digit[3]);
  const BoneScales clamped = bone_scales(huge, hand.rest);
  for (double s : clamped.scale) CHECK(s <= kMaxBoneScale);
}
