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

#include "config/assets.h"
#include "hand/hand_bones.h"
#include "hand/hand_template.h"
#include "hand/shape_adaption.h"
#include "passes/hand_skinning.h"
#include "sim/hand_model.h"

using namespace rt;
using namespace rt::hand;

namespace {

const std::filesystem::path kAssetsHandTemplate = rt::config::assets_dir() / "hand";

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
    const HandTemplate hand = load_hand_template(kAssetsHandTemplate, is_left);
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
  for (const auto& entry : std::filesystem::directory_iterator(kAssetsHandTemplate)) bytes += entry.file_size();
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
      const HandTemplate hand = committed ? load_hand_template(kAssetsHandTemplate, is_left) : build_hand_template(is_left);
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
      // A finger's tube is at most 13 mm thick (the thumb's), the forearm 35 mm; the wrist bone
      // carries the palm (4.5 cm either side of it at the knuckles) and the thumb's base.
      for (int bone = 0; bone < kBoneCount; ++bone) {
        INFO("bone " << bone_name(bone));
        CHECK(worst_by_bone[size_t(bone)] < (bone == kWristBone ? 0.055 : bone == kArmBone ? 0.036 : 0.014));
      }
      for (int d = 0; d < kDigitCount; ++d) {
        INFO("digit " << d << " reaches " << reach[size_t(d)] * 1000 << " mm past its tip joint");
        CHECK(reach[size_t(d)] > 0.002);  // the fingertip's cap: 5 to 8 mm
        CHECK(reach[size_t(d)] < 0.010);
      }
    }
}

TEST_CASE("The forearm: after the hand's triangles, round as the simulator's, from the elbow to the wrist") {
  for (bool is_left : {false, true}) {
    const HandTemplate hand = build_hand_template(is_left);
    INFO((is_left ? "left" : "right"));
    REQUIRE(hand.hand_index_count % 3 == 0);
    REQUIRE(hand.hand_index_count > 0);
    REQUIRE(hand.hand_index_count < hand.indices.size());
    CHECK(hand.palm_width_m == Approx(sim::palm_width_m(1.0)));
    CHECK(hand.arm_width_m == Approx(2 * 0.035));
    const double forearm = hand.rest[kArmBone].length_m;
    CHECK(forearm == Approx(0.25));
    // Vertices only the forearm uses: along -y from the wrist to the elbow's cap, within its
    // radius of the axis, weighted to the arm (blending into the wrist only near the wrist).
    std::vector<bool> in_hand(hand.vertices.size(), false);
    for (uint32_t i = 0; i < hand.hand_index_count; ++i) in_hand[hand.indices[i]] = true;
    double lowest = 0, widest = 0;
    size_t arm_only = 0;
    for (size_t t = hand.hand_index_count; t < hand.indices.size(); ++t) {
      const uint32_t i = hand.indices[t];
      REQUIRE_FALSE(in_hand[i]);
      const HandVertex& v = hand.vertices[i];
      const Eigen::Vector3d p(v.position_u[0], v.position_u[1], v.position_u[2]);
      CHECK(p.y() < 0.0);
      lowest = std::min(lowest, p.y());
      widest = std::max(widest, std::hypot(p.x(), p.z()));
      double arm = 0;
      for (int k = 0; k < 4; ++k)
        if (int(v.joints[k]) == kArmBone) arm += v.weights[k];
        else if (v.weights[k] > 0) CHECK(int(v.joints[k]) == kWristBone);
      if (p.y() < -0.04) CHECK(arm == Approx(1.0).margin(1e-6));
      arm_only += arm > 0.999;
    }
    CHECK(lowest == Approx(-forearm - 0.035).margin(1e-4));  // the elbow's round cap
    CHECK(widest == Approx(0.035).margin(1e-4));
    CHECK(arm_only > 200);
    // The hand's own triangles reach no further than 4 cm behind the wrist.
    for (uint32_t t = 0; t < hand.hand_index_count; ++t) CHECK(hand.vertices[hand.indices[t]].position_u[1] > -0.041f);
  }
}

TEST_CASE("Bad template files give an error that names the file and the problem") {
  const auto dir = std::filesystem::temp_directory_path() / "rt_bad_hand_template";
  std::filesystem::create_directories(dir);
  CHECK_THROWS_WITH(load_hand_template(dir / "nothing.gltf"), Catch::Contains("no such file"));
  std::ofstream(dir / "right_hand.gltf") << "{ not json";
  CHECK_THROWS_WITH(load_hand_template(dir, false), Catch::Contains("right_hand.gltf") && Catch::Contains("glTF"));
  // A template whose .bin is cut short.
  std::filesystem::copy_file(kAssetsHandTemplate / "left_hand.gltf", dir / "left_hand.gltf", std::filesystem::copy_options::overwrite_existing);
  std::filesystem::copy_file(kAssetsHandTemplate / "hand_skin.png", dir / "hand_skin.png", std::filesystem::copy_options::overwrite_existing);
  {
    std::ifstream in(kAssetsHandTemplate / "left_hand.bin", std::ios::binary);
    std::vector<char> bytes((std::istreambuf_iterator<char>(in)), {});
    std::ofstream(dir / "left_hand.bin", std::ios::binary).write(bytes.data(), std::streamsize(bytes.size() / 2));
  }
  CHECK_THROWS_AS(load_hand_template(dir, true), HandTemplateError);
  // A template without the forearm's split, or with one past its indices.
  std::filesystem::copy_file(kAssetsHandTemplate / "left_hand.bin", dir / "left_hand.bin", std::filesystem::copy_options::overwrite_existing);
  std::string gltf;
  {
    std::ifstream in(kAssetsHandTemplate / "left_hand.gltf");
    gltf.assign((std::istreambuf_iterator<char>(in)), {});
  }
  const size_t key = gltf.find("\"hand_index_count\"");
  REQUIRE(key != std::string::npos);
  auto with = [&](const std::string& replacement) {
    std::string changed = gltf;
    changed.replace(key, std::string("\"hand_index_count\"").size(), replacement);
    std::ofstream(dir / "left_hand.gltf") << changed;
  };
  with("\"hand_index_total\"");
  CHECK_THROWS_WITH(load_hand_template(dir, true), Catch::Contains("left_hand.gltf") && Catch::Contains("extras.hand_index_count"));
  with("\"hand_index_count\": 99999999, \"unused\"");
  CHECK_THROWS_WITH(load_hand_template(dir, true), Catch::Contains("hand_index_count"));
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

TEST_CASE("Shape adaption with widths: S_j scales across the bone by the width ratio, normals by the inverse transpose") {
  for (bool is_left : {false, true}) {
    const HandTemplate hand = build_hand_template(is_left);
    const TemplateWidths widths{hand.palm_width_m, hand.arm_width_m};
    // A hand 10% longer and 15% narrower than the template, with a 28 cm forearm 6 cm wide.
    const double k = 1.1, w = 0.85, arm_length = 0.28, arm_width = 0.06;
    HandSkeleton tracked = posed_hand(is_left, k, 0.0, Eigen::Vector3d(0, k * sim::palm_centre_uv().y(), 0));
    tracked.elbow = tracked.wrist - arm_length * tracked.direction;
    tracked.palm_width_m = w * hand.palm_width_m;
    tracked.arm_width_m = arm_width;
    const BoneScales scales = bone_scales(tracked, hand.rest, widths);
    REQUIRE(scales.ok());
    for (int bone = kWristBone; bone < kBoneCount; ++bone) {
      INFO(bone_name(bone));
      CHECK(scales.scale[bone] == Approx(k).epsilon(1e-9));
      CHECK(scales.across[bone] == Approx(w).epsilon(1e-9));
    }
    CHECK(scales.scale[kArmBone] == Approx(arm_length / 0.25).epsilon(1e-9));
    CHECK(scales.across[kArmBone] == Approx(arm_width / hand.arm_width_m).epsilon(1e-9));

    const RestSkeleton adapted = adapted_rest_skeleton(hand.rest, scales);
    const auto vertices = adapt_rest_mesh(hand.vertices, hand.rest, adapted, scales);
    REQUIRE(vertices.size() == hand.vertices.size());
    // The bind frames are axis-aligned in the palm (wrist bone: the identity at the wrist), so a
    // vertex on the wrist bone alone goes to (w x, k y, w z) and its normal to (x / w, y / k, z / w).
    size_t checked = 0;
    for (size_t i = 0; i < vertices.size(); ++i) {
      const HandVertex &before = hand.vertices[i], &after = vertices[i];
      for (int c = 0; c < 4; ++c) REQUIRE((std::isfinite(after.position_u[c]) && std::isfinite(after.normal_v[c])));
      CHECK(std::abs(Eigen::Vector3f(after.normal_v[0], after.normal_v[1], after.normal_v[2]).norm() - 1.0f) < 1e-5f);
      if (!(before.weights[0] == 1.0f && int(before.joints[0]) == kWristBone)) continue;
      const Eigen::Vector3d p(before.position_u[0], before.position_u[1], before.position_u[2]);
      const Eigen::Vector3d n(before.normal_v[0], before.normal_v[1], before.normal_v[2]);
      const Eigen::Vector3d expected(w * p.x(), k * p.y(), w * p.z());
      const Eigen::Vector3d expected_n = Eigen::Vector3d(n.x() / w, n.y() / k, n.z() / w).normalized();
      CHECK((Eigen::Vector3d(after.position_u[0], after.position_u[1], after.position_u[2]) - expected).norm() < 1e-6);
      CHECK((Eigen::Vector3d(after.normal_v[0], after.normal_v[1], after.normal_v[2]) - expected_n).norm() < 1e-5);
      ++checked;
    }
    CHECK(checked > 100);
    // The forearm is as wide and as long as the tracked one.
    double arm_half = 0, arm_low = 0;
    for (size_t i = 0; i < vertices.size(); ++i) {
      const Eigen::Vector3f p(vertices[i].position_u[0], vertices[i].position_u[1], vertices[i].position_u[2]);
      const Eigen::Vector3f q(hand.vertices[i].position_u[0], hand.vertices[i].position_u[1], hand.vertices[i].position_u[2]);
      if (q.y() < -0.1f) arm_half = std::max(arm_half, double(std::hypot(p.x(), p.z())));
      arm_low = std::min(arm_low, double(p.y()));
    }
    CHECK(arm_half == Approx(arm_width / 2).epsilon(1e-3));
    CHECK(arm_low == Approx(-arm_length * (1.0 + 0.035 / 0.25)).epsilon(1e-4));  // the elbow's cap scales along
    // Posed with the adapted skeleton, the fingers start where the narrowed palm puts them: this
    // skeleton's knuckles spread by k, not by w, so its tips are missed by (k - w) times the
    // knuckle's lateral offset (at most 4.5 cm); with a palm width that agrees they land exactly.
    const BonePose pose = pose_bones(tracked, adapted);
    REQUIRE(pose.ok());
    for (int d = 0; d < kDigitCount; ++d)
      CHECK((posed_tip(pose.frames, adapted, d) - tracked.digits[d][4]).norm() < (k - w) * 0.045 + 1e-9);
    HandSkeleton agreeing = tracked;
    agreeing.palm_width_m = k * hand.palm_width_m;
    const RestSkeleton fitted = adapted_rest_skeleton(hand.rest, bone_scales(agreeing, hand.rest, widths));
    const BonePose fitted_pose = pose_bones(agreeing, fitted);
    REQUIRE(fitted_pose.ok());
    for (int d = 0; d < kDigitCount; ++d)
      CHECK((posed_tip(fitted_pose.frames, fitted, d) - agreeing.digits[d][4]).norm() < 1e-9);
  }
}

TEST_CASE("Shape adaption with widths: missing, degenerate and wild widths and forearms") {
  const HandTemplate hand = build_hand_template(false);
  const TemplateWidths widths{hand.palm_width_m, hand.arm_width_m};
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  const double k = 0.9;
  const HandSkeleton base = posed_hand(false, k, 0.3, Eigen::Vector3d(0.02, 0.1, 0.3));
  auto require_usable = [&](const HandSkeleton& tracked) {
    const BoneScales scales = bone_scales(tracked, hand.rest, widths);
    REQUIRE(scales.ok());
    for (int bone = 0; bone < kBoneCount; ++bone) {
      REQUIRE(std::isfinite(scales.scale[bone]));
      REQUIRE(std::isfinite(scales.across[bone]));
      CHECK(scales.scale[bone] >= kMinBoneScale);
      CHECK(scales.across[bone] <= kMaxBoneScale);
    }
    const RestSkeleton adapted = adapted_rest_skeleton(hand.rest, scales);
    const auto vertices = adapt_rest_mesh(hand.vertices, hand.rest, adapted, scales);
    for (const HandVertex& v : vertices)
      for (int c = 0; c < 4; ++c) REQUIRE((std::isfinite(v.position_u[c]) && std::isfinite(v.normal_v[c])));
    const BonePose pose = pose_bones(tracked, adapted);
    REQUIRE(pose.ok());
    CHECK(all_finite(skin(pose.frames, adapted, vertices)));
    return scales;
  };
  SECTION("no widths: the paper's uniform scale per bone") {
    const BoneScales scales = require_usable(base);
    for (int bone = 0; bone < kBoneCount; ++bone) CHECK(scales.across[bone] == scales.scale[bone]);
    // And without template widths too.
    HandSkeleton with = base;
    with.palm_width_m = 0.07;
    const BoneScales no_reference = bone_scales(with, hand.rest);
    for (int bone = 0; bone < kBoneCount; ++bone) CHECK(no_reference.across[bone] == no_reference.scale[bone]);
  }
  SECTION("a palm width alone sets the forearm's width too") {
    HandSkeleton with = base;
    with.palm_width_m = 0.8 * hand.palm_width_m;
    const BoneScales scales = require_usable(with);
    CHECK(scales.across[kArmBone] == Approx(0.8));
    CHECK(scales.across[digit_bone(3, 2)] == Approx(0.8));
  }
  SECTION("zero, negative and infinite widths are not measurements; huge ones are clamped") {
    for (double bad : {0.0, -0.05, inf, nan}) {
      HandSkeleton with = base;
      with.palm_width_m = bad;
      with.arm_width_m = bad;
      const BoneScales scales = require_usable(with);
      for (int bone = 0; bone < kBoneCount; ++bone) CHECK(scales.across[bone] == scales.scale[bone]);
    }
    HandSkeleton huge = base;
    huge.palm_width_m = 10.0;
    huge.arm_width_m = 1e-6;
    const BoneScales scales = require_usable(huge);
    CHECK(scales.across[kWristBone] == kMaxBoneScale);
    CHECK(scales.across[kArmBone] == kMinBoneScale);
  }
  SECTION("an elbow missing or at the wrist: the forearm takes the palm's scale and is not drawn") {
    HandSkeleton missing = base;
    missing.elbow = Eigen::Vector3d::Constant(nan);
    HandSkeleton zero = base;
    zero.elbow = zero.wrist;
    HandSkeleton partial = base;
    partial.elbow.x() = nan;
    for (const HandSkeleton* tracked : {&missing, &zero, &partial}) {
      const BoneScales scales = require_usable(*tracked);
      CHECK(scales.scale[kArmBone] == Approx(scales.scale[kWristBone]));
      CHECK_FALSE(forearm_tracked(*tracked, hand.rest));
    }
    CHECK(forearm_tracked(base, hand.rest));
    HandSkeleton far = base;
    far.elbow = far.wrist - 2.0 * far.direction;
    CHECK_FALSE(forearm_tracked(far, hand.rest));
    CHECK(require_usable(far).scale[kArmBone] == kMaxBoneScale);
  }
}
