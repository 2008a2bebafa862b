// HandRenderer, the receiver's geometry hand: nothing before a pose, a held pose for a skeleton
// that cannot be posed (never a broken mesh), the shape fitted once, appearance adaption only
// beyond d_max, and its result moving the render's color towards the portrait's; its record read
// back from the GPU: waiting, a frame whose region is empty not counted, fitted, stale after K
// displayed frames; supersampled, a silhouette with partial coverage at its edge and the same area.
#include <cmath>
#include <limits>
#include <map>

#include "config/assets.h"
#include "pipeline/hand_renderer.h"
#include "geometry/target_view.h"
#include "sim/hand_model.h"
#include "support/gpu_test.h"

using namespace rt;

namespace {

const std::filesystem::path kTemplates = rt::config::assets_dir() / "hand";

HandSkeleton facing_hand(double z, double scale = 1.0) {
  sim::HandPlacement placement;
  placement.palm = Eigen::Vector3d(0.0, 0.02, z);
  Eigen::Matrix3d facing;
  facing << -Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(), -Eigen::Vector3d::UnitZ();
  placement.orientation = Eigen::Quaterniond(facing);
  placement.curl = 0.2;
  HandSkeleton hand = sim::build_hand(placement, false, scale);
  hand.elbow = hand.wrist - 0.25 * hand.direction;
  return hand;
}

double covered(const HostImage& mask) {
  double sum = 0;
  for (float m : mask.texels) sum += m;
  return sum;
}

Eigen::Vector3d mean_color(const HostImage& color, const HostImage& mask) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  double n = 0;
  for (uint32_t y = 0; y < color.height; ++y)
    for (uint32_t x = 0; x < color.width; ++x)
      if (mask.at(x, y) > 0.5f) sum += Eigen::Vector3d(color.at(x, y, 0), color.at(x, y, 1), color.at(x, y, 2)), ++n;
  return n > 0 ? Eigen::Vector3d(sum / n) : sum;
}

}  // namespace

TEST_CASE("HandRenderer draws nothing before a pose and holds the last pose for a broken skeleton") {
  test::NoValidationErrors no_errors;
  vk::Context& context = test::gpu();
  const Camera camera = target_view_camera(Eigen::Vector3d(0, 0.02, -0.7), Screen{}, 121, 67);
  pipeline::HandRenderer renderer(context, kTemplates, 121, 67);
  vk::FrameGraph graph(context, "test hand renderer");
  renderer.add_to(graph);
  graph.run();
  CHECK(covered(vk::download(context, renderer.mask())) == 0.0);

  renderer.set_pose(facing_hand(0.15, 1.1), camera);
  REQUIRE(renderer.has_pose());
  CHECK(renderer.shape_adapted());
  graph.run();
  const HostImage good = vk::download(context, renderer.depth());
  CHECK(covered(vk::download(context, renderer.mask())) > 50);
  CHECK(test::count_non_finite(good) == 0);

  HandSkeleton broken = facing_hand(0.3);
  broken.wrist = Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
  renderer.set_pose(broken, camera);
  CHECK_THAT(renderer.pose_error(), Catch::Contains("wrist"));
  graph.run();
  RT_REQUIRE_MATCHES(vk::download(context, renderer.depth()), good, 0.0, 0.0);

  // A camera of another size is a clear error, not a stretched render.
  CHECK_THROWS_WITH(renderer.set_pose(facing_hand(0.15), target_view_camera(Eigen::Vector3d(0, 0, -0.7), Screen{}, 64, 64)),
                    Catch::Contains("64x64"));
}

TEST_CASE("HandRenderer adapts its appearance towards the portrait's colors, inside d_max only until a frame beyond it fits") {
  test::NoValidationErrors no_errors;
  vk::Context& context = test::gpu();
  const uint32_t w = 160, h = 90;
  const Camera camera = target_view_camera(Eigen::Vector3d(0, 0.02, -0.7), Screen{}, w, h);
  pipeline::HandRenderer renderer(context, kTemplates, w, h);
  vk::FrameGraph graph(context, "test hand appearance");
  renderer.add_to(graph);
  vk::Image portrait_color(context, {"portrait color", w, h, PixelFormat::RGBA32F});
  vk::Image portrait_depth(context, {"portrait depth", w, h, PixelFormat::R32F});

  // Inside the ramp, before any fit: provisionally (an empty portrait: nothing agrees, nothing fits).
  renderer.set_pose(facing_hand(0.2), camera);
  graph.run();
  CHECK(renderer.appearance_adaption_possible());
  vk::upload(context, portrait_color, HostImage(w, h, PixelFormat::RGBA32F));
  vk::upload(context, portrait_depth, HostImage(w, h, PixelFormat::R32F));
  CHECK(renderer.adapt_appearance_from(portrait_color, portrait_depth));
  CHECK(renderer.appearance_status().phase == hand::AppearancePhase::Waiting);
  CHECK(renderer.awaits_first_fit());  // still the template's skin

  renderer.set_pose(facing_hand(0.5), camera);
  graph.run();
  const HostImage mask = vk::download(context, renderer.mask());
  const Eigen::Vector3d before = mean_color(vk::download(context, renderer.color()), mask);
  // The portrait: the same hand, a darker and redder skin, at the same depth.
  HostImage portrait = vk::download(context, renderer.color());
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x) {
      portrait.at(x, y, 0) *= 0.7f;
      portrait.at(x, y, 1) *= 0.45f;
      portrait.at(x, y, 2) *= 0.4f;
    }
  vk::upload(context, portrait_color, portrait);
  vk::upload(context, portrait_depth, vk::download(context, renderer.depth()));
  REQUIRE(renderer.adapt_appearance_from(portrait_color, portrait_depth));
  CHECK_FALSE(renderer.appearance_status().provisional);
  CHECK_FALSE(renderer.awaits_first_fit());
  const auto state = renderer.appearance_state();
  CHECK(state.header[0] == 1.0f);
  CHECK(state.header[2] > 16.0f);
  graph.run();
  const Eigen::Vector3d after = mean_color(vk::download(context, renderer.color()), mask);
  const Eigen::Vector3d target = before.cwiseProduct(Eigen::Vector3d(0.7, 0.45, 0.4));
  INFO("before " << before.transpose() << ", after " << after.transpose() << ", portrait " << target.transpose());
  CHECK((after - target).norm() < 0.25 * (before - target).norm());

  // A full view has fitted: inside d_max the cameras see only part of the hand, so no more there.
  renderer.set_pose(facing_hand(0.2), camera);
  CHECK_FALSE(renderer.appearance_adaption_possible());
  CHECK_FALSE(renderer.awaits_first_fit());
  CHECK_FALSE(renderer.adapt_appearance_from(portrait_color, portrait_depth));
  renderer.set_pose(facing_hand(0.5), camera);

  renderer.reset_appearance();
  graph.run();
  CHECK((mean_color(vk::download(context, renderer.color()), mask) - before).norm() < 1e-6);
  CHECK(renderer.awaits_first_fit());  // reset: the template's skin again
}

TEST_CASE("HandRenderer fits provisionally inside d_max, and starts afresh at the first frame beyond it") {
  test::NoValidationErrors no_errors;
  vk::Context& context = test::gpu();
  const uint32_t w = 160, h = 90;
  const Camera camera = target_view_camera(Eigen::Vector3d(0, 0.02, -0.7), Screen{}, w, h);
  pipeline::HandRenderer renderer(context, kTemplates, w, h);
  vk::FrameGraph graph(context, "test hand provisional appearance");
  renderer.add_to(graph);
  vk::Image portrait_color(context, {"portrait color", w, h, PixelFormat::RGBA32F});
  vk::Image portrait_depth(context, {"portrait depth", w, h, PixelFormat::R32F});
  // The portrait: one skin color wherever the hand is, at the hand's depth.
  auto tinted_portrait = [&](Eigen::Vector3f skin) {
    graph.run();
    const HostImage mask = vk::download(context, renderer.mask());
    HostImage portrait(w, h, PixelFormat::RGBA32F);
    for (uint32_t y = 0; y < h; ++y)
      for (uint32_t x = 0; x < w; ++x)
        if (mask.at(x, y) > 0.5f)
          for (uint32_t c = 0; c < 4; ++c) portrait.at(x, y, c) = c < 3 ? skin[int(c)] : 1.0f;
    vk::upload(context, portrait_color, portrait);
    vk::upload(context, portrait_depth, vk::download(context, renderer.depth()));
  };

  renderer.set_pose(facing_hand(0.2), camera);
  tinted_portrait({0.3f, 0.2f, 0.15f});  // what the cameras make of the arm close to the glass
  REQUIRE(renderer.adapt_appearance_from(portrait_color, portrait_depth));
  REQUIRE(renderer.adapt_appearance_from(portrait_color, portrait_depth));
  hand::AppearanceStatus status = renderer.appearance_status();
  CHECK(status.phase == hand::AppearancePhase::Fitted);
  CHECK(status.provisional);
  CHECK(status.frames_fitted == 2);
  const auto provisional = renderer.appearance_state();

  renderer.set_pose(facing_hand(0.5), camera);
  tinted_portrait({0.9f, 0.8f, 0.7f});
  REQUIRE(renderer.adapt_appearance_from(portrait_color, portrait_depth));
  status = renderer.appearance_status();
  CHECK_FALSE(status.provisional);
  CHECK(status.frames_fitted == 1);  // afresh: the provisional frames are gone
  const auto full = renderer.appearance_state();
  CHECK(full.header[1] == 1.0f);
  for (int c = 0; c < 3; ++c) CHECK(std::isfinite(full.image_mean[size_t(c)]));
  CHECK(full.image_mean[0] > provisional.image_mean[0] + 0.1f);  // the lighter portrait alone, not a mix
}

TEST_CASE("HandRenderer draws the forearm only with a tracked elbow at a plausible distance") {
  test::NoValidationErrors no_errors;
  vk::Context& context = test::gpu();
  const Camera camera = target_view_camera(Eigen::Vector3d(0, 0.02, -0.7), Screen{}, 121, 67);
  pipeline::HandRenderer renderer(context, kTemplates, 121, 67);
  vk::FrameGraph graph(context, "test hand renderer forearm");
  renderer.add_to(graph);
  const auto& hand = renderer.active_template();
  REQUIRE(hand.hand_index_count > 0);
  REQUIRE(hand.hand_index_count < hand.indices.size());

  HandSkeleton with_arm = facing_hand(0.15);
  with_arm.palm_width_m = sim::palm_width_m(0.9);
  with_arm.arm_width_m = 0.06;
  renderer.set_pose(with_arm, camera);
  REQUIRE(renderer.forearm_drawn());
  CHECK(renderer.drawn_index_count() == hand.indices.size());
  graph.run();
  const HostImage depth_arm = vk::download(context, renderer.depth());
  const double arm = covered(vk::download(context, renderer.mask()));
  CHECK(test::count_non_finite(depth_arm) == 0);

  const double nan = std::numeric_limits<double>::quiet_NaN();
  HandSkeleton no_elbow = with_arm;
  no_elbow.elbow = Eigen::Vector3d::Constant(nan);
  HandSkeleton zero_forearm = with_arm;
  zero_forearm.elbow = zero_forearm.wrist;
  HandSkeleton wild = with_arm;
  wild.elbow = wild.wrist - 3.0 * wild.direction;
  for (const HandSkeleton* skeleton : {&no_elbow, &zero_forearm, &wild}) {
    renderer.set_pose(*skeleton, camera);
    REQUIRE(renderer.has_pose());
    CHECK_FALSE(renderer.forearm_drawn());
    CHECK(renderer.drawn_index_count() == hand.hand_index_count);
    graph.run();
    const HostImage depth = vk::download(context, renderer.depth());
    CHECK(test::count_non_finite(depth) == 0);
    const double alone = covered(vk::download(context, renderer.mask()));
    CHECK(alone > 50);
    CHECK(alone < arm - 50);  // the forearm's pixels are gone
  }
}

TEST_CASE("HandRenderer's appearance status comes from the GPU's state: waiting, too small, fitted, stale") {
  test::NoValidationErrors no_errors;
  vk::Context& context = test::gpu();
  const uint32_t w = 160, h = 90;
  const Camera camera = target_view_camera(Eigen::Vector3d(0, 0.02, -0.7), Screen{}, w, h);
  pipeline::HandRendererOptions options;
  options.appearance_stale_frames = 5;
  pipeline::HandRenderer renderer(context, kTemplates, w, h, options);
  vk::FrameGraph graph(context, "test hand appearance status");
  renderer.add_to(graph);
  vk::Image portrait_color(context, {"portrait color", w, h, PixelFormat::RGBA32F});
  vk::Image portrait_depth(context, {"portrait depth", w, h, PixelFormat::R32F});
  CHECK(renderer.appearance_status().phase == hand::AppearancePhase::Waiting);

  renderer.set_pose(facing_hand(0.5), camera);
  graph.run();
  // An empty portrait: the adaption runs, but no pixel agrees, so nothing is fitted.
  vk::upload(context, portrait_color, HostImage(w, h, PixelFormat::RGBA32F));
  vk::upload(context, portrait_depth, HostImage(w, h, PixelFormat::R32F));
  REQUIRE(renderer.adapt_appearance_from(portrait_color, portrait_depth));
  hand::AppearanceStatus status = renderer.appearance_status();
  CHECK(status.phase == hand::AppearancePhase::Waiting);
  CHECK(status.frames_tried == 1);
  CHECK(status.frames_region_too_small == 1);
  CHECK_THAT(status.describe(), Catch::StartsWith("waiting: no frame with the hand seen by the cameras"));

  vk::upload(context, portrait_color, vk::download(context, renderer.color()));
  vk::upload(context, portrait_depth, vk::download(context, renderer.depth()));
  for (int frame = 0; frame < 3; ++frame) {
    renderer.note_frame_displayed();
    REQUIRE(renderer.adapt_appearance_from(portrait_color, portrait_depth));
  }
  status = renderer.appearance_status();
  CHECK(status.phase == hand::AppearancePhase::Fitted);
  CHECK(status.frames_fitted == 3);
  CHECK(status.describe() == "fitted from 3 frames");
  CHECK(status.last_region_pixels > 16.0);
  // The portrait is the template's own render: T' fits T, the statistics agree.
  for (int c = 0; c < 3; ++c) CHECK(std::abs(status.image.mean[size_t(c)] - status.mesh.mean[size_t(c)]) < 1e-3);
  std::vector<std::string> events;
  for (const auto& e : renderer.take_appearance_events()) events.push_back(e["change"]);
  CHECK(events == std::vector<std::string>{"rejected", "fitted"});

  renderer.set_pose(facing_hand(0.1), camera);  // at the glass: no adaption, the fit ages
  CHECK_FALSE(renderer.adapt_appearance_from(portrait_color, portrait_depth));
  renderer.sync_frames_displayed(3 + 5);
  CHECK(renderer.appearance_status().phase == hand::AppearancePhase::Fitted);
  renderer.note_frame_displayed();
  CHECK(renderer.appearance_status().phase == hand::AppearancePhase::Stale);
  CHECK(renderer.appearance_status().to_json()["state"] == "stale");

  renderer.reset_appearance();
  CHECK(renderer.appearance_status().phase == hand::AppearancePhase::Waiting);
}

TEST_CASE("HandRenderer's supersampling antialiases the silhouette and keeps the hand where it was") {
  test::NoValidationErrors no_errors;
  vk::Context& context = test::gpu();
  const Camera camera = target_view_camera(Eigen::Vector3d(0, 0.02, -0.7), Screen{}, 121, 67);
  std::map<uint32_t, HostImage> masks;
  for (uint32_t factor : {1u, 2u, 3u}) {
    pipeline::HandRendererOptions options;
    options.supersampling = factor;
    pipeline::HandRenderer renderer(context, kTemplates, 121, 67, options);
    vk::FrameGraph graph(context, "test hand supersampling");
    renderer.add_to(graph);
    renderer.set_pose(facing_hand(0.15), camera);
    graph.run();
    masks[factor] = vk::download(context, renderer.mask());
    const HostImage color = vk::download(context, renderer.color());
    CHECK(test::count_non_finite(masks[factor]) == 0);
    CHECK(test::count_non_finite(color) == 0);
    size_t partial = 0;
    for (float m : masks[factor].texels) partial += m > 0.0f && m < 1.0f;
    INFO("factor " << factor);
    if (factor == 1) CHECK(partial == 0);
    else CHECK(partial > 20);  // the edge pixels blend
  }
  // The same hand: its area and its mask agree within the edge pixels' share.
  const double area = covered(masks[1]);
  REQUIRE(area > 100);
  for (uint32_t factor : {2u, 3u}) {
    INFO("factor " << factor);
    CHECK(std::abs(covered(masks[factor]) - area) < 0.05 * area);
    double differing = 0;
    for (size_t i = 0; i < masks[1].texels.size(); ++i) differing += std::abs(masks[factor].texels[i] - masks[1].texels[i]);
    CHECK(differing < 0.25 * area);
  }
  pipeline::HandRendererOptions bad;
  bad.supersampling = 5;
  CHECK_THROWS_WITH(pipeline::HandRenderer(context, kTemplates, 121, 67, bad), Catch::Contains("1 to 4"));
}
