// The OpenCV peer of bench ibr against the warp and blend references on the small IBR rig: the
// same visibility and weights, colour to 2e-2 per channel (OpenCV's bilinear weights are fixed
// point in 1/32 pixel and it samples 8-bit colour to 8 bits, the reference in float) with 1 pixel
// plus 0.5 % of pixels allowed to differ (a sample on a visibility or image border may go either
// way, as in the warp's own test). Hard cases: NaN, Inf, negative and zero fused depths, no own
// depth anywhere, one view with k = 3. No NaN or Inf.
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <random>

#include "passes/ibr_blend.h"
#include "passes/ibr_foreground.h"
#include "passes/ibr_warp.h"
#include "pipeline/ibr_cpu_peer.h"
#include "support/ibr_rig.h"
#include "support/gpu_test.h"

using namespace rt;

namespace {

struct Compared {
  size_t differing = 0, non_finite = 0, covered = 0;
};

Compared compare(const cv::Mat& peer, const HostImage& reference, float tolerance) {
  Compared c;
  for (int y = 0; y < peer.rows; ++y)
    for (int x = 0; x < peer.cols; ++x) {
      const cv::Vec4f p = peer.at<cv::Vec4f>(y, x);
      bool differs = false;
      for (int k = 0; k < 4; ++k) {
        if (!std::isfinite(p[k])) ++c.non_finite;
        differs |= !(std::abs(p[k] - reference.at(uint32_t(x), uint32_t(y), uint32_t(k))) <= tolerance);
      }
      c.differing += differs;
      c.covered += p[3] > 0.5f;
    }
  return c;
}

passes::Portrait reference_portrait(const test::IbrRig& rig, const HostImage& fused, const HostImage& color,
                                    const HostImage& points, const passes::BlendSettings& blend = {}) {
  const passes::WarpedViews warped = passes::ibr_warp_reference(rig.table, fused, color, points);
  return passes::ibr_blend_reference(fused, warped.warped, warped.features, rig.table.camera_count, blend);
}

HostImage agreeing_points(std::mt19937& rng, const test::IbrRig& rig) {
  HostImage points = passes::ibr_foreground_reference(rig.table, test::random_depth_atlas(rng, rig, 0.05f),
                                                      passes::depth_ray_atlas(rig.cameras));
  for (size_t i = 3; i < points.texels.size(); i += 4)
    if (points.texels[i] > 0.0f) points.texels[i] = std::uniform_real_distribution<float>(0.55f, 0.85f)(rng);
  return points;
}

}  // namespace

TEST_CASE("the OpenCV peer computes what the warp and blend references do", "[ibr_cpu_peer]") {
  std::mt19937 rng(41);
  size_t covered = 0;
  for (const auto& [width, height] : {std::pair{29u, 19u}, {64u, 1u}, {1u, 33u}, {53u, 37u}}) {
    INFO(width << "x" << height);
    const test::IbrRig rig = test::ibr_rig(3, 37, 21, 41, 37, width, height);
    const HostImage fused = test::random_fused_depth(rng, width, height);
    const HostImage color = test::random_image(rng, 37, 21 * 3, PixelFormat::RGBA8);
    const HostImage points = agreeing_points(rng, rig);
    const pipeline::IbrCpuPeerResult peer =
        pipeline::run_ibr_cpu_peer(pipeline::cpu_peer_inputs(rig.table, fused, color, points), {}, {});
    const Compared c = compare(peer.portrait, reference_portrait(rig, fused, color, points).color, 2e-2f);
    INFO(c.differing << " of " << width * height << " pixels differ");
    REQUIRE(c.non_finite == 0);
    REQUIRE(c.differing <= 1 + size_t(width) * height / 200);
    covered += c.covered;
    REQUIRE(peer.times.total() >= 0.0);
  }
  REQUIRE(covered > 100);  // some pixels are seen, so the weights were compared, not only zeros
}

TEST_CASE("the OpenCV peer's hard cases", "[ibr_cpu_peer]") {
  std::mt19937 rng(42);
  const test::IbrRig rig = test::ibr_rig(2, 37, 21, 41, 37, 29, 19);
  const HostImage color = test::random_image(rng, 37, 42, PixelFormat::RGBA8);
  const HostImage points = agreeing_points(rng, rig);

  SECTION("NaN, Inf, negative and zero fused depths: nothing covered, no NaN") {
    HostImage fused(29, 19, PixelFormat::R32F);
    const float bad[] = {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(), -1.0f, 0.0f};
    for (size_t i = 0; i < fused.texels.size(); ++i) fused.texels[i] = bad[i % 4];
    const auto peer = pipeline::run_ibr_cpu_peer(pipeline::cpu_peer_inputs(rig.table, fused, color, points), {}, {});
    const Compared c = compare(peer.portrait, HostImage(29, 19, PixelFormat::RGBA32F, 0.0f), 0.0f);
    REQUIRE(c.non_finite == 0);
    REQUIRE(c.differing == 0);
  }
  SECTION("no view has an own depth: nothing covered") {
    const HostImage fused = test::random_fused_depth(rng, 29, 19);
    const HostImage none(points.width, points.height, PixelFormat::RGBA32F, 0.0f);
    const auto peer = pipeline::run_ibr_cpu_peer(pipeline::cpu_peer_inputs(rig.table, fused, color, none), {}, {});
    const Compared c = compare(peer.portrait, HostImage(29, 19, PixelFormat::RGBA32F, 0.0f), 0.0f);
    REQUIRE(c.non_finite == 0);
    REQUIRE(c.differing == 0);
  }
  SECTION("one view with k = 3 (fewer views than k), and k = 2 (the best view alone)") {
    const test::IbrRig one = test::ibr_rig(1, 37, 21, 41, 37, 29, 19);
    const HostImage fused = test::random_fused_depth(rng, 29, 19);
    const HostImage one_color = test::random_image(rng, 37, 21, PixelFormat::RGBA8);
    const HostImage one_points = agreeing_points(rng, one);
    for (int k : {3, 2}) {
      passes::BlendSettings blend;
      blend.best_views = k;
      const auto peer =
          pipeline::run_ibr_cpu_peer(pipeline::cpu_peer_inputs(one.table, fused, one_color, one_points), {}, blend);
      const Compared c =
          compare(peer.portrait, reference_portrait(one, fused, one_color, one_points, blend).color, 2e-2f);
      REQUIRE(c.non_finite == 0);
      REQUIRE(c.differing <= 1 + 29 * 19 / 200);
      REQUIRE(c.covered > 0);
    }
  }
}
