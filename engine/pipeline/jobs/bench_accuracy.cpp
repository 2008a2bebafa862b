// `remotetouch bench accuracy`: the image-based model's accuracy against its GPU time over a grid
// of configurations (pipeline/accuracy_grid.h), measured as `eval ibr` measures one
// (pipeline/ibr_evaluation.h) in one run on one device. The simulator renders each scene's frames
// once per camera resolution and portrait size, kept packed in memory, and every configuration
// of that group renders from them: the simulation costs more than most configurations.
// results.csv gains a row as each configuration ends, so a stopped run resumes where it stopped.
#include "pipeline/jobs.h"

#include <chrono>
#include <tuple>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include "config/json.h"
#include "ibr/camera_selection.h"
#include "pipeline/accuracy_grid.h"
#include "pipeline/accuracy_outputs.h"
#include "pipeline/accuracy_results.h"
#include "pipeline/gpu_session.h"
#include "pipeline/ibr_evaluation.h"
#include "pipeline/site_simulator.h"

namespace rt::pipeline {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// A host image in the GPU's byte layout: an rgba8 image takes a quarter of its float texels.
struct PackedImage {
  uint32_t width = 0, height = 0;
  PixelFormat format = PixelFormat::RGBA8;
  std::vector<std::byte> bytes;
  static PackedImage of(const HostImage& image) { return {image.width, image.height, image.format, pack_texels(image)}; }
  HostImage unpack() const { return unpack_texels(width, height, format, bytes.data()); }
};

struct CachedFrame {
  std::vector<std::string> camera_names;
  std::vector<uint64_t> timestamps_us;
  std::vector<PackedImage> color, depth_mm;
  PackedImage truth_color, truth_depth, truth_part;
  ibr::TouchingHand hand = ibr::TouchingHand::Right;

  std::vector<sim::RgbdImage> cameras() const {
    std::vector<sim::RgbdImage> images(camera_names.size());
    for (size_t k = 0; k < images.size(); ++k)
      images[k] = {camera_names[k], timestamps_us[k], color[k].unpack(), depth_mm[k].unpack()};
    return images;
  }
  PortraitTruth truth() const { return {truth_color.unpack(), truth_depth.unpack(), truth_part.unpack()}; }
};

struct SceneFrames {
  std::string scene;
  double resolution_scale = 0;
  std::vector<passes::IbrCameraModel> cameras;
  std::vector<Eigen::Vector3d> positions;
  Camera target;
  std::vector<CachedFrame> frames;
};

// The configurations that share the simulator's output: the same cameras and the same truth.
struct Group {
  double resolution_scale = 0;
  uint32_t width = 0, height = 0;
  bool operator<(const Group& other) const {
    return std::tie(resolution_scale, width, height) < std::tie(other.resolution_scale, other.width, other.height);
  }
};

SceneFrames simulate_scene(vk::Context& context, const std::string& name, const BenchAccuracyOptions& bench,
                           const RunOptions& options, const Group& group) {
  sim::Scene scene = sim::load_scene(sim::resolve_scene(name));
  const uint32_t frames = select_scene_frames(
      scene, {0, bench.frame_step, bench.frames_given ? std::optional(options.frames) : std::nullopt}, "bench accuracy");
  scene.color_supersampling = bench.supersample;
  if (group.resolution_scale > 0) scene.resolution_scale = group.resolution_scale;
  SiteSimulator simulator(context, scene, Site::A, group.width, group.height);
  SceneFrames out{name, scene.resolution_scale, simulator.renderer().camera_models(), {}, *simulator.renderer().target_view(), {}};
  for (const auto& camera : simulator.site().cameras) out.positions.push_back(camera.color_camera().position_in_site());
  for (uint32_t index = 0; index < frames; ++index) {
    simulator.seek(uint64_t(index) * bench.frame_step);
    const std::optional<sim::RgbdFrame> frame = simulator.next_frame();
    if (!frame) break;
    CachedFrame cached;
    for (const sim::RgbdImage& image : frame->cameras) {
      cached.camera_names.push_back(image.camera);
      cached.timestamps_us.push_back(image.timestamp_us);
      cached.color.push_back(PackedImage::of(image.color));
      cached.depth_mm.push_back(PackedImage::of(image.depth_mm));
    }
    cached.truth_color = PackedImage::of(simulator.renderer().target_color());
    cached.truth_depth = PackedImage::of(simulator.renderer().target_depth_m());
    cached.truth_part = PackedImage::of(simulator.renderer().target_part());
    const sim::PersonPose& pose = simulator.last_pose();
    cached.hand = ibr::touching_hand(pose.right_hand, pose.left_hand);
    out.frames.push_back(std::move(cached));
    std::fprintf(stderr, "\r  simulating %s at camera scale %g, %ux%u: frame %u/%u   ", name.c_str(), scene.resolution_scale,
                 group.width, group.height, index + 1, frames);
  }
  return out;
}

// A rough share of the work of a configuration, to tell the time left from the time taken so far:
// the portrait's samples, the views splatted and the refinement's sweep.
double work_estimate(const AccuracyConfig& config) {
  const double samples = config.portrait_scale * config.portrait_scale * config.ibr.supersample * config.ibr.supersample;
  const double refinement = config.ibr.refine ? 1.0 + 0.05 * config.ibr.refinement.hypotheses : 1.0;
  return 0.5 + samples * (0.5 + config.ibr.views / 8.0) * refinement;
}

std::string duration_text(double seconds) {
  char text[32];
  const int total = int(std::lround(seconds));
  if (total >= 60) std::snprintf(text, sizeof text, "%dm%02ds", total / 60, total % 60);
  else std::snprintf(text, sizeof text, "%ds", total);
  return text;
}

std::string joined_by(const std::vector<std::string>& words, const char* separator) {
  std::string text;
  for (const std::string& word : words) text += (text.empty() ? "" : separator) + word;
  return text;
}

// What must match for rows of two runs to be compared: the same frames, sizes and device.
nlohmann::json measurement_of(const RunOptions& options, const BenchAccuracyOptions& bench, const std::string& device) {
  return {{"scenes", bench.scenes},
          {"frame_step", bench.frame_step},
          {"frames_per_scene", bench.frames_given ? nlohmann::json(options.frames) : nlohmann::json("all")},
          {"width", options.width},
          {"height", options.height},
          {"supersample", bench.supersample},
          {"device", device}};
}

}  // namespace

int run_bench_accuracy(const RunOptions& options, const BenchAccuracyOptions& bench) {
  const Clock::time_point run_start = Clock::now();
  const std::vector<AccuracyConfig> configs = expand_grid(accuracy_grid(bench.grid));
  // A misnamed scene fails now, not after the first scenes were simulated.
  for (const std::string& scene : bench.scenes) sim::load_scene(sim::resolve_scene(scene));
  GpuSession session(options);
  vk::Context& context = session.context();
  std::filesystem::create_directories(options.out);

  // A run with other frames, sizes or device measured something else: refuse to mix them.
  const nlohmann::json measurement = measurement_of(options, bench, context.device_name());
  const std::filesystem::path run_file = options.out / "run.json";
  const std::filesystem::path csv = options.out / "results.csv";
  std::vector<AccuracyRow> rows;
  if (std::filesystem::exists(csv)) {
    if (!std::filesystem::exists(run_file) || config::read_json_file(run_file) != measurement)
      throw std::runtime_error(options.out.string() + " holds results measured otherwise (" +
                               (std::filesystem::exists(run_file) ? config::read_json_file(run_file).dump() : "no run.json") +
                               ", this run: " + measurement.dump() +
                               "); give the same scenes, frames, size and device to resume, or another --out");
    rows = read_accuracy_csv(csv);
  }
  std::ofstream(run_file) << measurement.dump(2) << "\n";

  std::vector<std::string> done;
  for (const AccuracyRow& row : rows) done.push_back(row.options);
  std::map<Group, std::vector<const AccuracyConfig*>> groups;
  double work_left = 0;
  size_t to_measure = 0;
  for (const AccuracyConfig& config : configs) {
    if (std::find(done.begin(), done.end(), accuracy_options(config, options.width, options.height)) != done.end()) continue;
    const auto [width, height] = portrait_size(config, options.width, options.height);
    groups[{config.resolution_scale, width, height}].push_back(&config);
    work_left += work_estimate(config);
    ++to_measure;
  }
  const std::string scenes = joined_by(bench.scenes, "+");
  std::printf("bench accuracy on %s: grid %s, %zu configurations (%zu already in %s), scenes %s, every %u%s frame%s, "
              "portraits %ux%u, simulated color and truth %ux%u samples a pixel\n",
              context.device_name().c_str(), bench.grid.c_str(), configs.size(), configs.size() - to_measure,
              csv.string().c_str(), scenes.c_str(), bench.frame_step, bench.frame_step == 1 ? "" : "th",
              bench.frames_given ? (", " + std::to_string(options.frames) + " a scene").c_str() : "", options.width,
              options.height, bench.supersample, bench.supersample);
  std::fflush(stdout);  // before the progress on stderr

  std::vector<std::string> failures;
  double work_done = 0, measure_s = 0, simulate_s = 0;
  size_t measured = 0, groups_simulated = 0;
  for (const auto& [group, members] : groups) {
    const Clock::time_point simulate_start = Clock::now();
    std::vector<SceneFrames> scene_frames;
    for (const std::string& scene : bench.scenes) scene_frames.push_back(simulate_scene(context, scene, bench, options, group));
    std::fprintf(stderr, "\n");
    simulate_s += seconds_since(simulate_start);
    ++groups_simulated;
    for (const AccuracyConfig* config : members) {
      const Clock::time_point start = Clock::now();
      const std::string name = accuracy_options(*config, options.width, options.height);
      IbrEvaluation evaluation;
      IbrSettings settings = config->ibr;
      settings.width = group.width;
      settings.height = group.height;
      uint32_t frame_index = 0;
      for (const SceneFrames& scene : scene_frames) {
        IbrRenderer renderer(context, scene.cameras, settings);
        for (size_t f = 0; f < scene.frames.size(); ++f) {
          const CachedFrame& frame = scene.frames[f];
          const auto selection = ibr::select_cameras(scene.positions, frame.hand, settings.views);
          evaluation.measure_frame(session, renderer, frame_index++, frame.cameras(), selection, scene.target, frame.truth());
          std::fprintf(stderr, "\r  [%zu/%zu] %s: %s frame %zu/%zu   ", measured + 1, to_measure,
                       name.empty() ? "the defaults" : name.c_str(), scene.scene.c_str(), f + 1, scene.frames.size());
        }
      }
      ++measured;
      measure_s += seconds_since(start);
      work_done += work_estimate(*config);
      const double left_s = measure_s / work_done * (work_left - work_done) +
                            simulate_s / double(groups_simulated) * double(groups.size() - groups_simulated);
      const ibr::PortraitMetrics& metrics = evaluation.metrics();
      if (const auto bad = evaluation.non_finite()) {
        failures.push_back("'" + (name.empty() ? std::string("the defaults") : name) + "': " + *bad + " is not finite");
        std::fprintf(stderr, "\n");
        std::printf("[%zu/%zu] %s: FAILED, %s is not finite\n", measured, to_measure, name.c_str(), bad->c_str());
        continue;
      }
      AccuracyRow row;
      row.options = name;
      row.ibr = settings;
      row.resolution_scale = scene_frames.front().resolution_scale;
      row.scenes = scenes;
      row.frames = frame_index;
      row.psnr_fg_db = metrics.psnr_fg_db();
      row.psnr_hand_db = metrics.psnr_hand_db();
      row.depth_mae_edge_mm = metrics.depth_mae_edge_mm();
      row.alpha_iou = metrics.alpha_iou();
      row.gpu_ms = evaluation.gpu_ms_quantile(0.5);
      row.gpu_ms_q1 = evaluation.gpu_ms_quantile(0.25);
      row.gpu_ms_q3 = evaluation.gpu_ms_quantile(0.75);
      row.wall_s = seconds_since(start);
      rows.push_back(row);
      mark_fronts(rows);
      write_accuracy_csv(csv, rows);
      std::fprintf(stderr, "\n");
      std::printf("[%zu/%zu] %s: psnr_fg %.2f dB, hand %.2f dB, edge depth %.2f mm, alpha IoU %.4f, %.1f GPU ms "
                  "(%.1f-%.1f); %s so far, about %s left\n",
                  measured, to_measure, name.empty() ? "the defaults" : name.c_str(), row.psnr_fg_db, row.psnr_hand_db,
                  row.depth_mae_edge_mm, row.alpha_iou, row.gpu_ms, row.gpu_ms_q1, row.gpu_ms_q3,
                  duration_text(seconds_since(run_start)).c_str(), duration_text(left_s).c_str());
      std::fflush(stdout);
    }
  }
  if (rows.empty()) throw std::runtime_error("bench accuracy: no configuration was measured without failing");
  mark_fronts(rows);
  write_accuracy_csv(csv, rows);

  AccuracyRunInfo info;
  info.command = "remotetouch bench accuracy --scenes " + joined_by(bench.scenes, ",") + " --grid " + bench.grid +
                 " --frame-step " + std::to_string(bench.frame_step) +
                 (bench.frames_given ? " --frames " + std::to_string(options.frames) : "") + " --width " +
                 std::to_string(options.width) + " --height " + std::to_string(options.height) +
                 (bench.supersample != 3 ? " --supersample " + std::to_string(bench.supersample) : "") + " --out " +
                 options.out.string();
  info.device = context.device_name();
  info.frames = "scenes " + scenes + ", every " + std::to_string(bench.frame_step) + "th frame" +
                (bench.frames_given ? " (" + std::to_string(options.frames) + " a scene)" : "") + ", " +
                std::to_string(rows.front().frames) + " frames a configuration";
  info.width = options.width;
  info.height = options.height;
  write_pareto_md(options.out / "pareto.md", rows, info);
  std::printf("\nthe front (psnr_fg_db against GPU ms), %s:\n", (options.out / "pareto.md").string().c_str());
  std::ifstream table(options.out / "pareto.md");
  for (std::string line; std::getline(table, line);)
    if (line.rfind("| ", 0) == 0) std::printf("%s\n", line.c_str());
  if (bench.plot) plot_accuracy(options.out);
  std::printf("written to %s (%s)\n", options.out.string().c_str(),
              bench.plot ? "results.csv, pareto.md, pareto.png" : "results.csv, pareto.md");
  if (!failures.empty()) {
    std::printf("\nFAILED: %zu configuration%s produced NaN or Inf:\n", failures.size(), failures.size() == 1 ? "" : "s");
    for (const std::string& failure : failures) std::printf("  %s\n", failure.c_str());
    return 1;
  }
  return 0;
}

}  // namespace rt::pipeline
