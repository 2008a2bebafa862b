// `remotetouch eval dual`: the receiver's whole chain, deterministic, frame by frame in order, for
// each user of a scene as the other site sees them: the sender's portrait for the receiver's eye,
// the remote skeleton at the portrait's capture time, shape and appearance adaption as the site
// runs them, Eq. 4, Eq. 5 and the composite; measured against the simulator's ground truth on
// the region of the user's hand and forearm, per touch phase and per variant of the fusion.
#include "pipeline/jobs.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <span>
#include <vector>

#include "evaluation/region_scores.h"
#include "evaluation/touch_phase.h"
#include "geometry/site_frames.h"
#include "ibr/camera_selection.h"
#include "pipeline/eval_dual_outputs.h"
#include "pipeline/gpu_session.h"
#include "pipeline/hand_renderer.h"
#include "pipeline/ibr_renderer.h"
#include "pipeline/limb_truth.h"
#include "pipeline/receiver_compositor.h"
#include "pipeline/site_simulator.h"
#include "config/assets.h"
#include "sim/tracker_sim.h"
#include "sim/tracker_space.h"
#include "tracking/skeleton_interpolation.h"
#include "tracking/skeleton_prediction.h"

namespace rt::pipeline {
namespace {

using evaluation::TouchPhase;

// The receiver's geometry hand in one configuration.
// Predicted: Full, posed from the skeleton carried forward to the display time.
enum class HandPath { Full, NoAppearance, NoShape, Predicted };

struct VariantSpec {
  const char* name;
  std::optional<HandPath> hand;  // none: the image-based model alone
};
const std::array<VariantSpec, 7> kVariants = {{{"image", std::nullopt},
                                               {"geometry", HandPath::Full},
                                               {"dual", HandPath::Full},
                                               {"dual_no_appearance", HandPath::NoAppearance},
                                               {"dual_no_shape", HandPath::NoShape},
                                               {"hard_switch", HandPath::Full},
                                               {"dual_predicted", HandPath::Predicted}}};
// hard_switch: the mesh alone below this distance, the image-based model alone above it.
constexpr double kHardSwitchM = 0.3;

// The distance Eq. 4 is given for a variant: NaN draws no geometry hand, 0 draws the mesh
// wherever it covers (alpha_g = 1).
float fusion_distance(const std::string& variant, double tracked_distance_m) {
  if (variant == "image") return NAN;
  if (variant == "geometry") return 0.0f;
  if (variant == "hard_switch") return tracked_distance_m < kHardSwitchM ? 0.0f : NAN;
  return float(tracked_distance_m);
}

struct HandRun {
  std::unique_ptr<HandRenderer> renderer;
  std::unique_ptr<vk::FrameGraph> graph;
  bool adapts_appearance = true;
  bool drawn = false;
  bool adapted_before_display = false;  // this frame's fit ran before the draw (awaits_first_fit)
  double distance_m = NAN;              // of its posed hand to the screen: what Eq. 4 is given
  HostImage color, mask;
};

// The drawn hand's samples up to the newest the receiver has, oldest first: the same hand (id
// and side) in each, for the prediction's fit.
std::vector<HandSkeleton> hand_history(std::span<const SkeletonSample> known, const HandSkeleton& hand,
                                       uint64_t history_us) {
  std::vector<HandSkeleton> history;
  for (const SkeletonSample& sample : known) {
    if (sample.timestamp_us + history_us < known.back().timestamp_us) continue;
    for (const HandSkeleton& candidate : sample.hands)
      if (candidate.id == hand.id && candidate.is_left == hand.is_left) history.push_back(candidate);
  }
  return history;
}

// Mean over the digits of the image distance between the mesh's tip joints and the true ones.
std::optional<double> tip_error_px(const HandRenderer& renderer, const HandSkeleton& truth, const Camera& view) {
  const auto tips = renderer.fingertips();
  double sum = 0;
  int counted = 0;
  for (int d = 0; d < kDigitCount; ++d) {
    const auto a = view.project(tips[size_t(d)]), b = view.project(truth.digits[size_t(d)][int(DigitJoint::Tip)]);
    if (a && b) sum += (*a - *b).norm(), ++counted;
  }
  if (counted == 0) return std::nullopt;
  return sum / counted;
}

}  // namespace

int run_eval_dual(const RunOptions& options, const EvalDualOptions& eval) {
  sim::Scene scene = sim::load_scene(sim::resolve_scene(eval.scene));
  const uint32_t frames = select_scene_frames(
      scene, {eval.first_frame, eval.frame_step, eval.frames_given ? std::optional(options.frames) : std::nullopt}, "eval dual");
  if (eval.resolution_scale > 0) scene.resolution_scale = eval.resolution_scale;
  std::vector<std::string> variants = eval.variants;
  if (variants.empty())
    for (const auto& spec : kVariants)
      if (spec.hand != HandPath::Predicted || eval.tracker_latency_ms > 0) variants.push_back(spec.name);
  if (!std::isfinite(eval.tracker_latency_ms) || eval.tracker_latency_ms < 0)
    throw std::invalid_argument("eval dual: --tracker-latency must be a number of milliseconds >= 0");
  const uint64_t latency_us = uint64_t(std::llround(eval.tracker_latency_ms * 1000.0));
  std::map<std::string, std::optional<HandPath>> variant_hand;
  for (const auto& spec : kVariants) variant_hand[spec.name] = spec.hand;
  for (const auto& name : variants)
    if (!variant_hand.count(name)) throw std::invalid_argument("eval dual: unknown variant '" + name + "'");

  GpuSession session(options);
  vk::Context& context = session.context();
  const uint32_t width = options.width, height = options.height;
  const std::filesystem::path template_dir = config::assets_dir() / "hand";
  std::filesystem::create_directories(options.out);
  DualEvalOutputs outputs(options.out);
  nlohmann::json report = {{"scene", eval.scene},
                           {"quality", eval.quality},
                           {"width", width},
                           {"height", height},
                           {"frames", frames},
                           {"first_frame", eval.first_frame},
                           {"frame_step", eval.frame_step},
                           {"variants", variants},
                           {"device", context.device_name()},
                           {"ibr", ibr_settings_json(eval.ibr)},
                           {"hand", hand_settings_json(eval.hand)},
                           {"tracker_latency_ms", eval.tracker_latency_ms}};
  std::printf("eval dual: scene %s, %u frames (every %u from %u), %ux%u, variants", eval.scene.c_str(), frames,
              eval.frame_step, eval.first_frame, width, height);
  for (const auto& name : variants) std::printf(" %s", name.c_str());
  std::printf(", on %s\n", context.device_name().c_str());

  for (const std::string& user_name : eval.users) {
    const Site site = user_name == "B" ? Site::B : Site::A;
    const sim::UserAppearance& user = scene.at(site).user;
    SiteSimulator simulator(context, scene, site, width, height);
    const Camera target = *simulator.renderer().target_view();

    // The sender: its image-based model as the site runs it.
    IbrSettings ibr_settings = eval.ibr;
    ibr_settings.width = width;
    ibr_settings.height = height;
    IbrRenderer ibr(context, simulator.renderer().camera_models(), ibr_settings);
    std::vector<Eigen::Vector3d> camera_positions;
    for (const auto& camera : simulator.site().cameras) camera_positions.push_back(camera.color_camera().position_in_site());

    // The remote skeletons: the whole 50 Hz stream of the scene, in the sender's frame.
    std::vector<SkeletonSample> skeletons;
    {
      sim::SimulatedHandTracker tracker = sim::make_simulated_tracker(scene, site);
      while (auto frame = tracker.next_frame())
        skeletons.push_back({frame->timestamp_us, sim::skeletons_in_site(*frame, simulator.site().tracker)});
    }

    // The receiver: one geometry hand per configuration the variants need.
    std::map<HandPath, HandRun> hands;
    for (const auto& name : variants) {
      const auto path = variant_hand.at(name);
      if (!path || hands.count(*path)) continue;
      HandRendererOptions hand_options = eval.hand;
      if (*path == HandPath::NoShape) hand_options.shape_adaption = false;
      HandRun run;
      run.renderer = std::make_unique<HandRenderer>(context, template_dir, width, height, hand_options);
      run.graph = std::make_unique<vk::FrameGraph>(context, "eval dual hand");
      run.renderer->add_to(*run.graph);
      run.adapts_appearance = *path != HandPath::NoAppearance;
      hands.emplace(*path, std::move(run));
    }
    ReceiverCompositor compositor(context, HostImage(width, height, PixelFormat::RGBA32F), /*keep_layers=*/true);
    vk::FrameGraph receiver_graph(context, "eval dual receiver");
    float fusion_distance_m = NAN;
    compositor.add_to(receiver_graph, [&] { return fusion_distance_m; });

    LimbTruthRenderer limb_truth(context, target);

    std::map<std::pair<TouchPhase, std::string>, evaluation::ScoreTotals> totals;
    uint64_t predicted_frames = 0, predicted_joints_behind_glass = 0;
    double predicted_lead_ms_sum = 0;
    for (uint32_t index = 0; index < frames; ++index) {
      simulator.seek(eval.first_frame + uint64_t(index) * eval.frame_step);
      const std::optional<sim::RgbdFrame> frame = simulator.next_frame();
      if (!frame) break;
      const sim::PersonPose& pose = simulator.last_pose();
      const ibr::TouchingHand side = ibr::touching_hand(pose.right_hand, pose.left_hand);
      const HostImage truth_color = simulator.renderer().target_color();
      const LimbTruth truth = limb_truth.measure(pose, user, truth_color, simulator.renderer().target_depth_m(),
                                                 simulator.renderer().target_part());
      const evaluation::HandRegion& region = truth.region;
      const std::optional<TouchPhase> phase = truth.phase;

      // The sender's portrait for the receiver's eye.
      ibr.prepare(frame->cameras, ibr::select_cameras(camera_positions, side, ibr_settings.views), target);
      session.run_frame(ibr.graph(), index);
      const HostImage portrait = vk::download(context, ibr.portrait());

      // The receiver's hand, posed from the skeleton at the portrait's capture time; under a
      // tracker latency, from the newest skeleton it has by then, held or carried forward.
      const uint64_t shown_us = frame->timestamp_us;
      std::span<const SkeletonSample> known(skeletons);
      if (latency_us > 0) {
        const uint64_t known_us = shown_us > latency_us ? shown_us - latency_us : 0;
        size_t count = 0;
        while (count < skeletons.size() && skeletons[count].timestamp_us <= known_us) ++count;
        known = known.first(count);
      }
      const HandsAtTime at_capture =
          latency_us > 0 ? hands_at(known, known.empty() ? 0 : known.back().timestamp_us) : hands_at(skeletons, shown_us);
      const HandSkeleton* drawn = hand_nearest_screen(at_capture.hands);
      std::optional<uint64_t> skeleton_gap_us;
      if (drawn) skeleton_gap_us = at_capture.gap_us[size_t(drawn - at_capture.hands.data())];
      std::optional<HandSkeleton> predicted;
      if (drawn && hands.count(HandPath::Predicted) && !known.empty()) {
        const SkeletonPredictionParameters prediction;
        const std::vector<HandSkeleton> history = hand_history(known, *drawn, prediction.history_us);
        predicted = predict_hand(history, shown_us, prediction);
        if (predicted) {
          ++predicted_frames;
          predicted_lead_ms_sum += double(shown_us - std::min(shown_us, history.back().timestamp_us)) / 1000.0;
          for (const Eigen::Vector3d& joint : predicted->hand_joints())
            if (joint.z() < 0) ++predicted_joints_behind_glass;
          if (predicted->has_elbow() && predicted->elbow.z() < 0) ++predicted_joints_behind_glass;
        }
      }
      double tracked_distance_m = NAN;
      for (auto& [path, run] : hands) {
        run.drawn = false;
        run.adapted_before_display = false;
        run.distance_m = NAN;
        const HandSkeleton* pose = path == HandPath::Predicted ? (predicted ? &*predicted : nullptr) : drawn;
        if (!pose) continue;
        run.renderer->set_pose(*pose, target);
        if (!run.renderer->has_pose()) continue;
        run.adapted_before_display = run.adapts_appearance && run.renderer->awaits_first_fit();
        if (run.adapted_before_display) run.renderer->adapt_appearance_from(ibr.portrait(), ibr.portrait_depth());
        run.graph->run();
        run.color = vk::download(context, run.renderer->color());
        run.mask = vk::download(context, run.renderer->mask());
        run.drawn = true;
        run.distance_m = run.renderer->hand_distance_m();
        if (path != HandPath::Predicted) tracked_distance_m = run.distance_m;
      }

      FrameRecord record{user_name, uint32_t(frame->index), double(frame->timestamp_us) * 1e-6, truth.distance_m,
                         tracked_distance_m, phase, skeleton_gap_us, count_set(region.hand_arm)};
      vk::upload(context, compositor.portrait, portrait);
      std::optional<HandPath> uploaded;
      for (const std::string& name : variants) {
        const std::optional<HandPath> path = variant_hand.at(name);
        const HandRun* run = path ? &hands.at(*path) : nullptr;
        const bool with_hand = run && run->drawn;
        if (with_hand && uploaded != path) {
          vk::upload(context, compositor.hand_color, run->color);
          vk::upload(context, compositor.hand_mask, run->mask);
          uploaded = path;
        }
        fusion_distance_m = with_hand ? fusion_distance(name, run->distance_m) : NAN;
        receiver_graph.run();
        const HostImage fused = vk::download(context, *compositor.fused);
        const evaluation::FrameScore score = evaluation::score_frame(fused, truth_color, region);
        const std::optional<double> tip = with_hand ? tip_error_px(*run->renderer, truth.hand, target) : std::nullopt;
        if (phase) totals[{*phase, name}].add(score, tip);
        outputs.add_frame(record, name, score, tip, fused, truth_color, region);
      }

      // Appearance adaption after the display, from the portrait just shown, as the site does:
      // what it fits is what the next frames sample (the first fit ran before the draw, above).
      for (auto& [path, run] : hands) {
        if (run.drawn && run.adapts_appearance && !run.adapted_before_display)
          run.renderer->adapt_appearance_from(ibr.portrait(), ibr.portrait_depth());
        run.renderer->note_frame_displayed();
      }
      std::fprintf(stderr, "\r  user %s: frame %u/%u", user_name.c_str(), index + 1, frames);
    }
    std::fprintf(stderr, "\n");

    nlohmann::json& user_report = report["users"][user_name];
    user_report["skin_rgb"] = {user.skin_rgb.x(), user.skin_rgb.y(), user.skin_rgb.z()};
    user_report["hand_scale"] = user.hand_scale;
    if (hands.count(HandPath::Predicted))
      user_report["prediction"] = {
          {"frames", predicted_frames},
          {"mean_skeleton_to_display_ms", predicted_frames ? nlohmann::json(predicted_lead_ms_sum / double(predicted_frames)) : nlohmann::json()},
          {"joints_behind_glass", predicted_joints_behind_glass}};
    for (const auto& [key, scores] : totals)
      user_report["phases"][evaluation::phase_name(key.first)][key.second] = scores.to_json();
    if (hands.count(HandPath::Full)) {
      const hand::AppearanceStatus status = hands.at(HandPath::Full).renderer->appearance_status();
      user_report["appearance"] = status.to_json();
      const hand::ShadingFit& shading = hands.at(HandPath::Full).renderer->shading_fit();
      user_report["appearance_shading"] = shading.to_json();
      std::printf("user %s: appearance adaption %s; light estimate %s from %llu frames\n", user_name.c_str(),
                  status.describe().c_str(), shading.to_json()["state"].get<std::string>().c_str(),
                  static_cast<unsigned long long>(shading.frames()));
    }
    double ibr_ms = 0;
    for (const auto& timing : ibr.graph().timings()) ibr_ms += timing.median_ms;
    user_report["gpu_ms_per_frame"]["ibr"] = ibr_ms;
  }

  report["region"] = "the truth's hand and forearm that reach for the glass, where visible, dilated by 3 px; de_hand over "
                     "its fully covered hand pixels; iou_hand_arm of alpha >= 0.5 within 12 px of it";
  report["phases"] = "d = distance of the averaged true hand joints to the screen: far >= 0.4 m, approach 0.2-0.4, "
                     "near 0.02-0.2, touching < 0.02";
  report["goals"] = check_goals(report);
  std::ofstream(options.out / "metrics.json") << report.dump(2) << "\n";
  print_summary(report);
  outputs.finish();
  std::cout << "written to " << (options.out / "metrics.json").string() << ", frames.csv and the sheets\n";
  if (eval.plots) plot_eval_dual(options.out);
  session.report_capture();
  return 0;
}

}  // namespace rt::pipeline
