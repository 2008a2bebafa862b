// hand_skinning pass: GPU against the double-precision reference on random vertices of odd
// counts with random bone matrices, on the template over random hand poses, and on the hard
// cases (one bone, zero weights but one, huge translations). Tolerance: 2e-6 m absolute plus
// 1e-6 relative on positions (float32 arithmetic), 1e-5 on unit normals; never NaN.
#include <cmath>
#include <limits>
#include <random>

#include "hand/hand_bones.h"
#include "hand/hand_template.h"
#include "hand/shape_adaption.h"
#include "passes/hand_skinning.h"
#include "sim/hand_model.h"
#include "support/gpu_test.h"
#include "support/pass_harness.h"

using namespace rt;
using passes::BoneMatrices;
using passes::HandVertex;
using passes::SkinnedVertex;

namespace {

std::vector<SkinnedVertex> run_gpu_hand_skinning(const std::vector<HandVertex>& rest, const BoneMatrices& bones) {
  const passes::HandSkinningPass pass(test::gpu());
  test::PassHarness gpu("hand_skinning");
  pass.add_to(gpu.graph(), gpu.input_buffer("rest vertices", rest), gpu.input_buffer("bone transforms", bones),
              gpu.output_buffer<SkinnedVertex>("skinned vertices", rest.size()), [n = uint32_t(rest.size())] { return n; });
  return gpu.run().values<SkinnedVertex>("skinned vertices");
}

double require_matches_hand_skinning(const std::vector<SkinnedVertex>& gpu, const std::vector<SkinnedVertex>& reference) {
  REQUIRE(gpu.size() == reference.size());
  double worst = 0;
  for (size_t i = 0; i < gpu.size(); ++i)
    for (int c = 0; c < 4; ++c) {
      const double g = gpu[i].position_u[c], r = reference[i].position_u[c];
      REQUIRE(std::isfinite(g));
      INFO("vertex " << i << " channel " << c);
      REQUIRE(std::abs(g - r) <= 2e-6 + 1e-6 * std::abs(r));
      if (c < 3) worst = std::max(worst, std::abs(g - r));
      const double gn = gpu[i].normal_v[c], rn = reference[i].normal_v[c];
      REQUIRE(std::isfinite(gn));
      REQUIRE(std::abs(gn - rn) <= 1e-5);
    }
  return worst;
}

BoneMatrices random_rigid_bones(std::mt19937& rng, double translation) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  BoneMatrices bones;
  for (auto& bone : bones) {
    Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
    t.linear() = Eigen::Quaterniond(unit(rng), unit(rng), unit(rng), unit(rng) + 1.5).normalized().toRotationMatrix();
    t.translation() = translation * Eigen::Vector3d(unit(rng), unit(rng), unit(rng));
    for (int column = 0; column < 4; ++column)
      for (int row = 0; row < 4; ++row) bone[size_t(column * 4 + row)] = float(t.matrix()(row, column));
  }
  return bones;
}

std::vector<HandVertex> random_vertices(std::mt19937& rng, size_t count) {
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f), positive(0.0f, 1.0f);
  std::uniform_int_distribution<int> bone(0, RT_HAND_BONES - 1);
  std::vector<HandVertex> vertices(count);
  for (HandVertex& v : vertices) {
    v.position_u = {0.2f * unit(rng), 0.2f * unit(rng), 0.2f * unit(rng), positive(rng)};
    Eigen::Vector3f n(unit(rng), unit(rng), unit(rng));
    n = n.norm() > 1e-3f ? n.normalized() : Eigen::Vector3f::UnitZ();
    v.normal_v = {n.x(), n.y(), n.z(), positive(rng)};
    float sum = 0;
    for (int k = 0; k < 4; ++k) {
      v.joints[size_t(k)] = float(bone(rng));
      v.weights[size_t(k)] = positive(rng);
      sum += v.weights[size_t(k)];
    }
    for (auto& w : v.weights) w /= sum;
  }
  return vertices;
}

}  // namespace

TEST_CASE("hand_skinning matches the reference on random vertices and bones of odd counts") {
  test::NoValidationErrors no_errors;
  std::mt19937 rng(11);
  for (size_t count : {size_t(1), size_t(63), size_t(65), size_t(1001)}) {
    INFO(count << " vertices");
    const auto vertices = random_vertices(rng, count);
    const auto bones = random_rigid_bones(rng, 1.0);
    require_matches_hand_skinning(run_gpu_hand_skinning(vertices, bones), passes::hand_skinning_reference(vertices, bones));
  }
}

TEST_CASE("hand_skinning of the template over random hand poses: the GPU error stays far below a millimetre") {
  test::NoValidationErrors no_errors;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> unit(-1.0, 1.0), curl(0.0, 1.0);
  for (bool is_left : {false, true}) {
    const hand::HandTemplate hand = hand::build_hand_template(is_left);
    for (int trial = 0; trial < 3; ++trial) {
      sim::HandPlacement placement;
      placement.palm = Eigen::Vector3d(0.3 * unit(rng), 0.2 * unit(rng), 0.2 + 0.2 * curl(rng));
      placement.orientation = Eigen::Quaterniond(unit(rng), unit(rng), unit(rng), unit(rng) + 1.5).normalized();
      placement.curl = curl(rng);
      HandSkeleton skeleton = sim::build_hand(placement, is_left, 0.9 + 0.2 * curl(rng));
      skeleton.elbow = skeleton.wrist - 0.25 * skeleton.direction;
      const hand::BonePose pose = hand::pose_bones(skeleton, hand.rest);
      REQUIRE(pose.ok());
      const auto bones = hand::skinning_matrices(pose.frames, hand.rest);
      CHECK(require_matches_hand_skinning(run_gpu_hand_skinning(hand.vertices, bones), passes::hand_skinning_reference(hand.vertices, bones)) < 1e-5);
    }
  }
}

TEST_CASE("hand_skinning of the forearm, shape-adapted with widths: random poses, a zero-length forearm, an elbow missing") {
  test::NoValidationErrors no_errors;
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> unit(-1.0, 1.0), positive(0.0, 1.0);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (bool is_left : {false, true}) {
    const hand::HandTemplate hand = hand::build_hand_template(is_left);
    for (int trial = 0; trial < 6; ++trial) {
      INFO((is_left ? "left" : "right") << " trial " << trial);
      sim::HandPlacement placement;
      placement.palm = Eigen::Vector3d(0.3 * unit(rng), 0.2 * unit(rng), 0.2 + 0.2 * positive(rng));
      placement.orientation = Eigen::Quaterniond(unit(rng), unit(rng), unit(rng), unit(rng) + 1.5).normalized();
      placement.curl = positive(rng);
      const double scale = 0.85 + 0.3 * positive(rng);
      HandSkeleton skeleton = sim::build_hand(placement, is_left, scale);
      // A forearm bent away from the hand's direction by up to ~35 degrees, or none.
      const Eigen::Vector3d bend = 0.35 * Eigen::Vector3d(unit(rng), unit(rng), unit(rng));
      const double forearm = 0.2 + 0.1 * positive(rng);
      skeleton.elbow = trial == 4 ? Eigen::Vector3d::Constant(nan)
                       : trial == 5 ? skeleton.wrist
                                    : Eigen::Vector3d(skeleton.wrist - forearm * (skeleton.direction + bend).normalized());
      skeleton.palm_width_m = sim::palm_width_m(scale);
      skeleton.arm_width_m = 0.055 + 0.02 * positive(rng);
      const hand::BoneScales scales = hand::bone_scales(skeleton, hand.rest, {hand.palm_width_m, hand.arm_width_m});
      REQUIRE(scales.ok());
      const hand::RestSkeleton adapted = hand::adapted_rest_skeleton(hand.rest, scales);
      const auto vertices = hand::adapt_rest_mesh(hand.vertices, hand.rest, adapted, scales);
      const hand::BonePose pose = hand::pose_bones(skeleton, adapted);
      REQUIRE(pose.ok());
      const auto bones = hand::skinning_matrices(pose.frames, adapted);
      const auto reference = passes::hand_skinning_reference(vertices, bones);
      CHECK(require_matches_hand_skinning(run_gpu_hand_skinning(vertices, bones), reference) < 1e-5);
      CHECK(hand::forearm_tracked(skeleton, hand.rest) == (trial < 4));
      if (trial >= 4) continue;
      // The forearm's own vertices (arm weight only) lie on the tracked elbow-wrist segment's
      // tube: within half the tracked arm width of the axis, between the elbow's cap and the wrist.
      const Eigen::Vector3d axis = (skeleton.wrist - skeleton.elbow).normalized();
      for (size_t t = hand.hand_index_count; t < hand.indices.size(); ++t) {
        const uint32_t i = hand.indices[t];
        if (!(vertices[i].weights[0] == 1.0f && int(vertices[i].joints[0]) == hand::kArmBone)) continue;
        const Eigen::Vector3d p(reference[i].position_u[0], reference[i].position_u[1], reference[i].position_u[2]);
        const double along = (p - skeleton.elbow).dot(axis);
        CHECK(along >= -0.035 * forearm / hand.rest[hand::kArmBone].length_m - 1e-6);  // the cap, scaled along
        CHECK(along <= forearm);
        CHECK((p - skeleton.elbow - along * axis).norm() <= skeleton.arm_width_m / 2 + 1e-6);
      }
    }
  }
}

TEST_CASE("hand_skinning hard cases: one bone, zero weights, far translations, a zero matrix") {
  test::NoValidationErrors no_errors;
  std::mt19937 rng(5);
  auto vertices = random_vertices(rng, 37);
  for (size_t i = 0; i < vertices.size(); ++i) {
    vertices[i].weights = {1.0f, 0.0f, 0.0f, 0.0f};  // a single influence
    vertices[i].joints = {float(i % RT_HAND_BONES), 0.0f, 0.0f, 0.0f};
  }
  const auto far = random_rigid_bones(rng, 1000.0);
  require_matches_hand_skinning(run_gpu_hand_skinning(vertices, far), passes::hand_skinning_reference(vertices, far));
  // An all-zero transform (a bone never posed) must not turn normals into NaN.
  BoneMatrices zero{};
  require_matches_hand_skinning(run_gpu_hand_skinning(vertices, zero), passes::hand_skinning_reference(vertices, zero));
}
