// The simulated site as the rest of the system sees it: cameras that lose the hand near the
// glass by geometry alone, depth equal to the ground truth with effects off, a rendered hand
// that sits on the tracker's joints, and recordings that replay exactly.
#include <filesystem>

#include "config/assets.h"
#include "pipeline/site_simulator.h"
#include "sim/default_site.h"
#include "sim/motion.h"
#include "sim/person_mesh.h"
#include "sim/recording.h"
#include "support/gpu_test.h"
#include "support/hands.h"

using namespace rt;

namespace {

constexpr double kScale = 0.25;  // of the cameras' resolutions: enough pixels for a palm

// The seated user at rest with the right palm at (0.1, 0.0, z), facing the screen.
sim::PersonPose pose_with_palm_at(const sim::SiteDescription& site, double z) {
  sim::PersonPose pose = sim::evaluate_motion({}, site.seat, {}, 0.0);
  pose.right_hand = test::flat_hand(0.1, 0.0, z);
  pose.right_arm.wrist = pose.right_hand.wrist;
  pose.right_arm.elbow = pose.right_hand.wrist + Eigen::Vector3d(0.05, -0.2, 0.2);
  return pose;
}

int cameras_seeing_palm(double z) {
  const sim::SiteDescription site = sim::make_default_site();
  std::vector<pipeline::RgbdCameraSpec> specs;
  for (const auto& camera : site.cameras) specs.push_back(pipeline::camera_spec(camera, {}, kScale));
  pipeline::RgbdRenderer renderer(test::gpu(), specs);
  const sim::PersonPose pose = pose_with_palm_at(site, z);
  renderer.render(sim::person_mesh(pose, {}), 1);
  int seeing = 0;
  for (size_t k = 0; k < specs.size(); ++k) {
    const Camera& depth_camera = specs[k].depth;
    // The palm's surface towards the screen, where the cameras look from.
    const Eigen::Vector3d palm_surface = pose.right_hand.palm - Eigen::Vector3d(0, 0, 0.012);
    const auto pixel = depth_camera.project(palm_surface);
    if (!pixel) continue;
    const long x = std::lround(pixel->x()), y = std::lround(pixel->y());
    if (x < 0 || y < 0 || x >= long(depth_camera.intrinsics.width) || y >= long(depth_camera.intrinsics.height)) continue;
    const HostImage truth = renderer.depth_view_truth(k);
    const HostImage depth = renderer.depth_mm(k);
    const double expected_z = (depth_camera.camera_from_site * palm_surface).z();
    const float seen_z = truth.at(uint32_t(x), uint32_t(y));
    // Seen: a valid depth sample within a couple of centimetres of the palm (not the body
    // behind it, not an occluder in front of it), and in the color image, which the image-based
    // model needs as much. (A bottom corner's 120-degree depth view reaches a palm on the glass
    // at a grazing angle; its 90-degree color view does not.)
    const auto color_pixel = specs[k].color.project(palm_surface);
    const bool in_color = color_pixel && color_pixel->x() >= 0 && color_pixel->y() >= 0 &&
                           color_pixel->x() < specs[k].color.intrinsics.width &&
                           color_pixel->y() < specs[k].color.intrinsics.height;
    if (depth.at(uint32_t(x), uint32_t(y)) > 0 && std::abs(seen_z - expected_z) < 0.02 && in_color) ++seeing;
  }
  return seeing;
}

}  // namespace

TEST_CASE("the palm is seen by at least four cameras at 0.5 m and by none on the glass", "[simulated_site][gpu]") {
  test::NoValidationErrors no_errors;
  CHECK(cameras_seeing_palm(0.5) >= 4);
  CHECK(cameras_seeing_palm(0.005) == 0);
}

TEST_CASE("with effects off the depth images are the ground truth in millimetres", "[simulated_site][gpu]") {
  test::NoValidationErrors no_errors;
  const sim::SiteDescription site = sim::make_default_site();
  std::vector<pipeline::RgbdCameraSpec> specs;
  for (const auto& camera : site.cameras) specs.push_back(pipeline::camera_spec(camera, {}, 0.1));
  pipeline::RgbdRenderer renderer(test::gpu(), specs);
  renderer.render(sim::person_mesh(pose_with_palm_at(site, 0.4), {}), 3);
  size_t valid = 0;
  for (size_t k = 0; k < specs.size(); ++k) {
    const HostImage truth = renderer.depth_view_truth(k), depth = renderer.depth_mm(k);
    for (size_t i = 0; i < truth.texels.size(); ++i) {
      const float z = truth.texels[i];
      const float expected = z >= float(specs[k].depth_model.range_min_m) && z <= float(specs[k].depth_model.range_max_m)
                                 ? std::floor(z * 1000.0f + 0.5f)
                                 : 0.0f;
      REQUIRE(depth.texels[i] == expected);
      valid += expected > 0;
    }
  }
  CHECK(valid > 300);  // the user is in view: the comparison is not vacuous
}

TEST_CASE("a site with lens distortion is refused, not rendered as a pinhole", "[simulated_site]") {
  sim::SiteDescription site = sim::make_default_site();
  site.cameras[2].depth.distortion.k1 = 0.1;
  CHECK_THROWS_WITH(pipeline::camera_spec(site.cameras[2], {}, 1.0), Catch::Contains(site.cameras[2].name) &&
                                                                  Catch::Contains("distortion is not simulated"));
}

TEST_CASE("the rendered hand is built on the tracker's joints", "[simulated_site]") {
  // Every bone capsule of the hand mesh keeps its surface at its radius from the segment
  // between two tracked joints: the joints lie on the rendered fingers' axes, to < 1 mm.
  const HandSkeleton hand = test::flat_hand(0.1, 0.0, 0.2);
  std::vector<sim::MeshVertex> mesh;
  sim::append_hand(mesh, hand, 1.0, {0.8f, 0.6f, 0.5f});
  const Eigen::Vector3d a = hand.joint(Digit::Index, DigitJoint::Dip), b = hand.joint(Digit::Index, DigitJoint::Tip);
  // The distal phalanx of the index finger is the 8th capsule (thumb 4, index 4).
  const size_t per_capsule = mesh.size() / 21;  // 20 bones and the palm, all of the same detail
  double worst = 0.0, radius = -1.0;
  for (size_t i = 7 * per_capsule; i < 8 * per_capsule; ++i) {
    const Eigen::Vector3d p(mesh[i].position_part[0], mesh[i].position_part[1], mesh[i].position_part[2]);
    const double t = std::clamp((p - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
    const double distance = (p - (a + t * (b - a))).norm();
    if (radius < 0) radius = distance;
    worst = std::max(worst, std::abs(distance - radius));
  }
  CHECK(worst < 1e-3);
  CHECK(radius > 0.005);
  CHECK(radius < 0.012);
}

TEST_CASE("a recorded simulation replays exactly", "[simulated_site][gpu]") {
  test::NoValidationErrors no_errors;
  sim::Scene scene = sim::load_scene(rt::config::assets_dir() / "scenes" / "clap.json");
  scene.frame_count = 2;
  scene.resolution_scale = 0.05;
  const auto dir = std::filesystem::temp_directory_path() / ("remotetouch-test-simulated-" + std::to_string(getpid()));
  std::filesystem::remove_all(dir);
  pipeline::SiteSimulator simulator(test::gpu(), scene, Site::A);
  std::vector<sim::RgbdFrame> frames;
  {
    // The calibration at the site's own size, with the scale the images were recorded at.
    nlohmann::json calibration = sim::site_to_json(scene.at(Site::A).site);
    calibration["recorded_scale"] = scene.resolution_scale;
    sim::RecordingWriter writer(dir, calibration);
    while (auto frame = simulator.next_frame()) {
      writer.write_frame(*frame);
      frames.push_back(std::move(*frame));
    }
  }
  REQUIRE(frames.size() == 2);
  sim::ReplayRgbdSource replay(dir);
  for (const auto& expected : frames) {
    const auto frame = replay.next_frame();
    REQUIRE(frame);
    REQUIRE(frame->cameras.size() == expected.cameras.size());
    for (size_t k = 0; k < expected.cameras.size(); ++k) {
      RT_REQUIRE_MATCHES(frame->cameras[k].color, expected.cameras[k].color, 0.0, 0.0);
      RT_REQUIRE_MATCHES(frame->cameras[k].depth_mm, expected.cameras[k].depth_mm, 0.0, 0.0);
    }
  }
}
