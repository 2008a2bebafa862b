#include "pipeline/jobs.h"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <iostream>
#include <nlohmann/json.hpp>
#include <random>
#include "config/assets.h"
#include "pipeline/gpu_session.h"
#include "pipeline/hand_renderer.h"
#include "geometry/target_view.h"
#include "hand/color_space.h"
#include "image/image_io.h"
#include "passes/person_raster.h"
#include "sim/hand_model.h"
#include "sim/person_mesh.h"

namespace rt::pipeline {

namespace {

const std::filesystem::path kTemplateDir = config::assets_dir() / "hand";
const Eigen::Vector3d kRemoteEye(0.0, 0.05, -0.7);  // the local viewer's eye in the remote site's frame

struct SyntheticUser {
  std::string name;
  Eigen::Vector3f skin_rgb;
  double hand_scale;
};
// Skin tones and hand sizes of the scenes' users (assets/scenes) and one between them.
const std::vector<SyntheticUser> kUsers = {{"light", {0.87f, 0.70f, 0.58f}, 1.05},
                                           {"medium", {0.62f, 0.44f, 0.33f}, 1.15},
                                           {"dark", {0.45f, 0.30f, 0.22f}, 0.88}};

// The hand facing the remote viewer (palm towards the screen), fingers up, turned a little.
HandSkeleton true_hand(const SyntheticUser& user, const Eigen::Vector3d& palm, double curl, double turn_rad, bool is_left) {
  sim::HandPlacement placement;
  placement.palm = palm;
  Eigen::Matrix3d facing;
  facing << -Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(), -Eigen::Vector3d::UnitZ();
  placement.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(turn_rad, Eigen::Vector3d(0.3, 1.0, 0.2).normalized()) * facing);
  placement.curl = curl;
  HandSkeleton hand = sim::build_hand(placement, is_left, user.hand_scale);
  hand.elbow = hand.wrist - 0.25 * user.hand_scale * hand.direction + Eigen::Vector3d(0, 0, 0.05);
  // What the simulated tracker reports for this user (tracker_sim.cpp): the palm's width from
  // the hand's size, the forearm's from the simulator's forearm capsule.
  hand.palm_width_m = sim::palm_width_m(user.hand_scale);
  hand.arm_width_m = sim::kArmWidthM;
  return hand;
}

// The true hand and forearm as the simulator draws them (person_mesh.cpp): capsules through the
// joints, the forearm a capsule of sim::kForearmRadiusM from the elbow to the wrist.
std::vector<passes::MeshVertex> true_mesh(const HandSkeleton& truth, const SyntheticUser& user) {
  std::vector<passes::MeshVertex> mesh;
  sim::append_hand(mesh, truth, user.hand_scale, user.skin_rgb);
  sim::append_capsule(mesh, truth.elbow, truth.wrist, sim::kForearmRadiusM, sim::kForearmRadiusM, truth.palm_normal,
                      float(RT_PART_BODY), user.skin_rgb, user.skin_rgb, 0.0f);
  return mesh;
}

// Intersection over union of the mesh's mask (coverage >= 0.5) and the truth's coverage (any
// part: the truth render holds only the hand and its forearm). Writes `overlay` (both: skin
// white, the mesh alone: green, the truth alone: red) when given.
double silhouette_iou(const HostImage& mesh_mask, const HostImage& truth_part, HostImage* overlay = nullptr) {
  size_t both = 0, either = 0;
  if (overlay) *overlay = HostImage(mesh_mask.width, mesh_mask.height, PixelFormat::RGBA32F);
  for (uint32_t y = 0; y < mesh_mask.height; ++y)
    for (uint32_t x = 0; x < mesh_mask.width; ++x) {
      const bool mesh = mesh_mask.at(x, y) >= 0.5f, truth = truth_part.at(x, y) != float(RT_PART_NONE);
      both += mesh && truth;
      either += mesh || truth;
      if (overlay) {
        const float r = truth ? 1.0f : 0.0f, g = mesh ? 1.0f : 0.0f, b = mesh && truth ? 1.0f : 0.0f;
        overlay->at(x, y, 0) = r, overlay->at(x, y, 1) = g, overlay->at(x, y, 2) = b, overlay->at(x, y, 3) = 1.0f;
      }
    }
  return either ? double(both) / double(either) : 1.0;
}

// Where the silhouettes are compared: the palm centre's distance to the screen.
struct SilhouettePlace {
  const char* name;
  double palm_z;
};
const SilhouettePlace kSilhouettePlaces[] = {{"far", 0.45}, {"near", 0.10}, {"glass", 0.015}};

// What the tracker reports: the true joints with 1 mm of Gaussian jitter.
HandSkeleton tracked(const HandSkeleton& truth, std::mt19937& rng) {
  std::normal_distribution<double> jitter(0.0, 0.001);
  HandSkeleton out = truth;
  auto shake = [&](Eigen::Vector3d& p) { p += Eigen::Vector3d(jitter(rng), jitter(rng), jitter(rng)); };
  shake(out.wrist);
  shake(out.palm);
  shake(out.elbow);
  for (auto& digit : out.digits)
    for (auto& joint : digit) shake(joint);
  // The tracker's thumb metacarpal has zero length whatever the noise.
  out.digits[0][int(DigitJoint::Carp)] = out.digits[0][int(DigitJoint::Mcp)];
  out.confidence = 1.0f;
  return out;
}

double mean_tip_error_mm(const HandRenderer& renderer, const HandSkeleton& truth) {
  double sum = 0;
  const auto tips = renderer.fingertips();
  for (int d = 0; d < kDigitCount; ++d) sum += (tips[size_t(d)] - truth.digits[size_t(d)][int(DigitJoint::Tip)]).norm();
  return 1000.0 * sum / kDigitCount;
}

struct ColorResult {
  double de2000 = 0, de76 = 0;
  size_t pixels = 0;
};

ColorResult color_difference(const HostImage& mesh_color, const HostImage& mesh_mask, const HostImage& truth_color,
                               const HostImage& truth_part) {
  ColorResult result;
  for (uint32_t y = 0; y < mesh_color.height; ++y)
    for (uint32_t x = 0; x < mesh_color.width; ++x) {
      if (mesh_mask.at(x, y) < 0.5f || truth_part.at(x, y) != float(RT_PART_HAND)) continue;
      const Eigen::Vector3d a = hand::rgb_to_cielab({mesh_color.at(x, y, 0), mesh_color.at(x, y, 1), mesh_color.at(x, y, 2)});
      const Eigen::Vector3d b = hand::rgb_to_cielab({truth_color.at(x, y, 0), truth_color.at(x, y, 1), truth_color.at(x, y, 2)});
      result.de2000 += hand::delta_e_2000(a, b);
      result.de76 += hand::delta_e_76(a, b);
      ++result.pixels;
    }
  if (result.pixels) result.de2000 /= double(result.pixels), result.de76 /= double(result.pixels);
  return result;
}

// What the best unlit hand could score: every pixel of the same set at the skin's true albedo.
// The ground truth is shaded and the mesh is drawn unlit (as the paper's), so the shading left
// in the truth is an error no color transfer removes.
double unlit_floor_de2000(const HostImage& mesh_mask, const HostImage& truth_color, const HostImage& truth_part,
                          const Eigen::Vector3f& albedo) {
  const Eigen::Vector3d albedo_lab = hand::rgb_to_cielab(albedo.cast<double>());
  double sum = 0;
  size_t pixels = 0;
  for (uint32_t y = 0; y < mesh_mask.height; ++y)
    for (uint32_t x = 0; x < mesh_mask.width; ++x) {
      if (mesh_mask.at(x, y) < 0.5f || truth_part.at(x, y) != float(RT_PART_HAND)) continue;
      sum += hand::delta_e_2000(albedo_lab, hand::rgb_to_cielab({truth_color.at(x, y, 0), truth_color.at(x, y, 1), truth_color.at(x, y, 2)}));
      ++pixels;
    }
  return pixels ? sum / double(pixels) : 0.0;
}

}  // namespace

int run_eval_hand(const RunOptions& options) {
  GpuSession session(options);
  vk::Context& context = session.context();
  const uint32_t width = options.width, height = options.height;
  const Camera camera = target_view_camera(kRemoteEye, Screen{}, width, height);
  std::filesystem::create_directories(options.out);
  nlohmann::json metrics;
  metrics["device"] = context.device_name();
  metrics["width"] = width;
  metrics["height"] = height;

  // 1. Skinning: the GPU's vertices against the double-precision reference, random poses.
  double skinning_max_err = 0;
  {
    HandRendererOptions no_adaption;
    no_adaption.shape_adaption = false;
    HandRenderer renderer(context, kTemplateDir, width, height, no_adaption);
    vk::FrameGraph graph(context, "eval hand skinning");
    renderer.add_to(graph);
    std::mt19937 rng(17);
    std::uniform_real_distribution<double> unit(-1.0, 1.0), curl(0.0, 1.0);
    for (int trial = 0; trial < 12; ++trial) {
      sim::HandPlacement placement;
      placement.palm = Eigen::Vector3d(0.3 * unit(rng), 0.2 * unit(rng), 0.1 + 0.4 * curl(rng));
      placement.orientation = Eigen::Quaterniond(unit(rng), unit(rng), unit(rng), unit(rng) + 1.5).normalized();
      placement.curl = curl(rng);
      HandSkeleton skeleton = sim::build_hand(placement, trial % 2 == 1, 0.85 + 0.3 * curl(rng));
      // The forearm too: most trials with an elbow, some without one or with a zero-length forearm.
      skeleton.elbow = trial % 4 == 3 ? Eigen::Vector3d::Constant(std::nan(""))
                       : trial % 4 == 2 ? skeleton.wrist
                                        : Eigen::Vector3d(skeleton.wrist - (0.2 + 0.1 * curl(rng)) * skeleton.direction);
      renderer.set_pose(skeleton, camera);
      graph.run();
      const auto bytes = vk::download(context, renderer.skinned_vertices());
      const auto reference = passes::hand_skinning_reference(renderer.active_rest_vertices(), renderer.bone_matrices());
      for (size_t i = 0; i < reference.size(); ++i) {
        shader_abi::SkinnedVertex v;
        std::memcpy(&v, bytes.data() + i * sizeof(v), sizeof(v));
        for (int c = 0; c < 3; ++c)
          skinning_max_err = std::max(skinning_max_err, double(std::abs(v.position_u[c] - reference[i].position_u[c])));
        if (!std::isfinite(v.position_u[0])) skinning_max_err = std::numeric_limits<double>::infinity();
      }
    }
  }
  metrics["skinning_max_err_m"] = skinning_max_err;

  // 2 and 3, per synthetic user.
  const passes::PersonRasterPass truth_raster(context);
  vk::Buffer truth_mesh(context, {"true hand mesh", 200000 * sizeof(passes::MeshVertex)});
  uint32_t truth_vertices = 0;
  vk::Image truth_color(context, {"true hand color", width, height, PixelFormat::RGBA8});
  vk::Image truth_depth(context, {"true hand depth", width, height, PixelFormat::R32F});
  vk::Image truth_part(context, {"true hand part", width, height, PixelFormat::R32F});
  vk::Image truth_depth_buffer(context, {"true hand depth buffer", width, height, PixelFormat::D32F});
  vk::Image portrait_color(context, {"portrait color (ground truth)", width, height, PixelFormat::RGBA32F});
  vk::FrameGraph truth_graph(context, "eval hand ground truth");
  const auto view = passes::raster_view(camera, 0.05, 20.0);
  truth_raster.add_to(truth_graph, truth_mesh, [&] { return truth_vertices; }, [view] { return view; },
                      {&truth_color, &truth_depth, &truth_part, &truth_depth_buffer}, "truth_raster");

  double tip_before = 0, tip_after = 0;
  std::map<std::string, std::pair<double, double>> iou;  // place -> mean over users before, after
  std::vector<double> de_before, de_after, de_floor;
  for (const SyntheticUser& user : kUsers) {
    HandRenderer renderer(context, kTemplateDir, width, height);
    vk::FrameGraph graph(context, "eval hand " + user.name);
    renderer.add_to(graph);
    std::mt19937 rng(uint32_t(29 + 7 * (&user - kUsers.data())));
    std::uniform_real_distribution<double> unit(-1.0, 1.0), curl(0.0, 0.8);

    // Fingertips over poses, the template's shape (before) and the adapted one (after).
    HandRendererOptions fixed;
    fixed.shape_adaption = false;
    HandRenderer unadapted(context, kTemplateDir, width, height, fixed);
    vk::FrameGraph unadapted_graph(context, "eval hand " + user.name + " unadapted");
    unadapted.add_to(unadapted_graph);
    double before = 0, after = 0;
    const int poses = 8;
    for (int p = 0; p < poses; ++p) {
      const HandSkeleton truth = true_hand(user, Eigen::Vector3d(0.1 * unit(rng), 0.05 * unit(rng), 0.1 + 0.4 * curl(rng)),
                                           curl(rng), 0.6 * unit(rng), p % 2 == 1);
      const HandSkeleton seen = tracked(truth, rng);
      unadapted.set_pose(seen, camera);
      renderer.set_pose(seen, camera);
      before += mean_tip_error_mm(unadapted, truth);
      after += mean_tip_error_mm(renderer, truth);
    }
    before /= poses;
    after /= poses;

    // Color: the true hand (capsules through its joints, skin shaded as the cameras see it)
    // 45 cm from the screen, beyond d_max, where appearance adaption runs.
    const HandSkeleton truth = true_hand(user, Eigen::Vector3d(0.04, 0.0, kSilhouettePlaces[0].palm_z), 0.25, 0.2, false);
    const std::vector<passes::MeshVertex> mesh = true_mesh(truth, user);
    truth_vertices = uint32_t(mesh.size());
    vk::upload(context, truth_mesh, std::as_bytes(std::span(mesh)));
    truth_graph.run();
    const HostImage truth_rgba8 = vk::download(context, truth_color), truth_parts = vk::download(context, truth_part);
    HostImage portrait(width, height, PixelFormat::RGBA32F);
    for (size_t i = 0; i < portrait.texels.size(); ++i) portrait.texels[i] = truth_rgba8.texels[i];
    vk::upload(context, portrait_color, portrait);

    renderer.reset_appearance();
    renderer.request_shape_adaption();
    const HandSkeleton seen = tracked(truth, rng);
    renderer.set_pose(seen, camera);
    graph.run();
    const ColorResult color_before =
        color_difference(vk::download(context, renderer.color()), vk::download(context, renderer.mask()), truth_rgba8, truth_parts);
    write_image(options.out / ("hand_" + user.name + "_before.png"), vk::download(context, renderer.color()));
    int adapted_frames = 0;
    for (int frame = 0; frame < 6; ++frame) {
      renderer.set_pose(tracked(truth, rng), camera);
      graph.run();
      adapted_frames += renderer.adapt_appearance_from(portrait_color, truth_depth) ? 1 : 0;
    }
    graph.run();
    const HostImage mask_after = vk::download(context, renderer.mask());
    const ColorResult color_after = color_difference(vk::download(context, renderer.color()), mask_after, truth_rgba8, truth_parts);
    const double unlit_floor = unlit_floor_de2000(mask_after, truth_rgba8, truth_parts, user.skin_rgb);
    write_image(options.out / ("hand_" + user.name + "_after.png"), vk::download(context, renderer.color()));
    write_image(options.out / ("hand_" + user.name + "_truth.png"), truth_rgba8);
    const auto state = renderer.appearance_state();

    // Silhouettes of hand and forearm against the truth's, far (the pose above), near and at
    // the glass: the template's shape (before) and the adapted one (after).
    nlohmann::json silhouettes;
    for (const SilhouettePlace& place : kSilhouettePlaces) {
      const HandSkeleton placed = true_hand(user, Eigen::Vector3d(0.04, 0.0, place.palm_z), 0.25, 0.2, false);
      const std::vector<passes::MeshVertex> placed_mesh = true_mesh(placed, user);
      truth_vertices = uint32_t(placed_mesh.size());
      vk::upload(context, truth_mesh, std::as_bytes(std::span(placed_mesh)));
      truth_graph.run();
      const HostImage parts = vk::download(context, truth_part);
      const HandSkeleton placed_seen = tracked(placed, rng);
      unadapted.set_pose(placed_seen, camera);
      renderer.set_pose(placed_seen, camera);
      unadapted_graph.run();
      graph.run();
      HostImage overlay;
      const double iou_before = silhouette_iou(vk::download(context, unadapted.mask()), parts);
      const double iou_after = silhouette_iou(vk::download(context, renderer.mask()), parts, &overlay);
      write_image(options.out / ("hand_" + user.name + "_silhouette_" + place.name + ".png"), overlay);
      silhouettes[place.name] = {{"iou_before", iou_before}, {"iou_after", iou_after}, {"forearm_drawn", renderer.forearm_drawn()}};
      iou[place.name].first += iou_before / double(kUsers.size());
      iou[place.name].second += iou_after / double(kUsers.size());
    }

    metrics["users"][user.name] = {
        {"skin_rgb", {user.skin_rgb.x(), user.skin_rgb.y(), user.skin_rgb.z()}},
        {"hand_scale", user.hand_scale},
        {"tip_err_mm_before", before},
        {"tip_err_mm_after", after},
        {"color_de_before", color_before.de2000},
        {"color_de_after", color_after.de2000},
        {"color_de76_before", color_before.de76},
        {"color_de76_after", color_after.de76},
        {"color_de_unlit_floor", unlit_floor},
        {"color_pixels", color_after.pixels},
        {"appearance_frames", adapted_frames},
        {"appearance_region_pixels", state.header[2]},
        {"silhouette_iou", silhouettes},
    };
    metrics["color_de_before_" + user.name] = color_before.de2000;
    metrics["color_de_after_" + user.name] = color_after.de2000;
    tip_before += before / double(kUsers.size());
    tip_after += after / double(kUsers.size());
    de_before.push_back(color_before.de2000);
    de_after.push_back(color_after.de2000);
    de_floor.push_back(unlit_floor);
  }
  metrics["tip_err_mm_before"] = tip_before;
  metrics["tip_err_mm_after"] = tip_after;
  double mean_before = 0, mean_after = 0;
  for (size_t i = 0; i < de_before.size(); ++i) mean_before += de_before[i] / double(de_before.size()), mean_after += de_after[i] / double(de_after.size());
  metrics["color_de_before"] = mean_before;
  metrics["color_de_after"] = mean_after;
  metrics["color_metric"] = "CIEDE2000 (CIELAB of linear sRGB, D65), mean over pixels that are hand in both the mesh render and the ground truth";
  metrics["portrait"] = "the simulator's ground-truth target view (capsule hand, shaded albedo) stands in for the image-based portrait";
  metrics["tracking"] = "true joints with 1 mm Gaussian jitter, the simulated tracker's palm and arm widths; shape adaption from the first such frame";
  for (const SilhouettePlace& place : kSilhouettePlaces) {
    metrics["silhouette_iou_before_" + std::string(place.name)] = iou[place.name].first;
    metrics["silhouette_iou_after_" + std::string(place.name)] = iou[place.name].second;
  }
  metrics["silhouette_metric"] =
      "intersection over union of the mesh's mask (>= 0.5) and the true hand+forearm coverage, palm 45 cm (far), 10 cm (near) "
      "and 1.5 cm (glass) from the screen; before: the template's shape, after: shape adaption to the tracked lengths and widths";
  metrics["tip_metric"] = "mean over the five digits of |mesh tip joint - true tip joint|, 8 poses per user, both hands";

  std::ofstream(options.out / "metrics.json") << metrics.dump(2) << "\n";
  std::printf("hand evaluation at %ux%u on %s\n", width, height, context.device_name().c_str());
  std::printf("%-26s %12.3g\n", "skinning_max_err_m", skinning_max_err);
  std::printf("%-26s %12s %12s %12s %12s\n", "", "before", "after", "ratio", "unlit floor");
  std::printf("%-26s %12.2f %12.2f %12.2f\n", "tip_err_mm", tip_before, tip_after, tip_before > 0 ? tip_after / tip_before : 0.0);
  for (size_t i = 0; i < kUsers.size(); ++i)
    std::printf("%-26s %12.2f %12.2f %12.2f %12.2f\n", ("color_de (" + kUsers[i].name + ")").c_str(), de_before[i], de_after[i],
                de_before[i] > 0 ? de_after[i] / de_before[i] : 0.0, de_floor[i]);
  std::printf("%-26s %12.2f %12.2f %12.2f\n", "color_de (mean)", mean_before, mean_after, mean_before > 0 ? mean_after / mean_before : 0.0);
  for (const SilhouettePlace& place : kSilhouettePlaces)
    std::printf("%-26s %12.3f %12.3f\n", ("silhouette_iou (" + std::string(place.name) + ")").c_str(), iou[place.name].first,
                iou[place.name].second);
  std::printf("color difference: CIEDE2000; portrait: the simulator's ground truth; unlit floor: the true albedo, unshaded\nwritten to %s\n",
              (options.out / "metrics.json").string().c_str());
  return 0;
}

}  // namespace rt::pipeline
