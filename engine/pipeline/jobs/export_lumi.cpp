// `remotetouch export lumi`: per frame, the image-based model up to its warp, then the network's
// input tensors computed by lumi_input's C++ reference (the same values the GPU pass gives, to
// its test's tolerance) and the simulator's truth box-filtered to the network's resolution.
//
// frame_NNNN.bin, all little-endian float32 planes of small_width x small_height, in order:
//   inputs (views, RT_LUMI_INPUT_CHANNELS), coverage (views), truth premultiplied rgb (3), truth
//   alpha (1), hand coverage (1: the fraction of the block that is hand in the truth).
// index.json: the sizes, the channel names and the frames.
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "ibr/camera_selection.h"
#include "pipeline/gpu_session.h"
#include "pipeline/ibr_renderer.h"
#include "pipeline/jobs.h"
#include "pipeline/lumi_export.h"
#include "pipeline/site_simulator.h"
#include "passes/lumi_input.h"
#include "shared/config.h"
#include "shared/lumi_net.h"

namespace rt::pipeline {
namespace {

vk::Image& written_by(vk::FrameGraph& graph, const std::string& pass, const std::string& image_name) {
  for (const auto& [name, image] : graph.written_images())
    if (name == pass && image->name() == image_name) return *image;
  throw std::logic_error("export lumi: the image-based model's graph has no '" + image_name + "' from " + pass);
}

// Box filter of one channel to the network's grid, the same blocks as lumi_input's.
std::vector<float> block_mean(const HostImage& image, uint32_t channel, uint32_t scale, float (*value)(float)) {
  const uint32_t sw = passes::lumi_small_size(image.width, scale), sh = passes::lumi_small_size(image.height, scale);
  std::vector<float> out(size_t(sw) * sh);
  for (uint32_t cy = 0; cy < sh; ++cy)
    for (uint32_t cx = 0; cx < sw; ++cx) {
      double sum = 0.0;
      int pixels = 0;
      for (uint32_t y = cy * scale; y < std::min(image.height, (cy + 1) * scale); ++y)
        for (uint32_t x = cx * scale; x < std::min(image.width, (cx + 1) * scale); ++x, ++pixels)
          sum += value(image.at(x, y, channel));
      out[size_t(cy) * sw + cx] = float(sum / std::max(pixels, 1));
    }
  return out;
}

void write_floats(std::ofstream& out, const std::vector<float>& values) {
  out.write(reinterpret_cast<const char*>(values.data()), std::streamsize(values.size() * sizeof(float)));
}

}  // namespace

int run_export_lumi(const RunOptions& options, const ExportLumiOptions& e) {
  sim::Scene scene = sim::load_scene(sim::resolve_scene(e.scene));
  const uint32_t frames = select_scene_frames(
      scene, {e.first_frame, e.frame_step, e.frames_given ? std::optional(options.frames) : std::nullopt}, "export lumi");
  scene.color_supersampling = e.supersample;
  GpuSession session(options);
  vk::Context& context = session.context();
  SiteSimulator simulator(context, scene, e.site == "B" ? Site::B : Site::A, options.width, options.height);
  const Camera target = *simulator.renderer().target_view();
  std::vector<Eigen::Vector3d> positions;
  for (const auto& camera : simulator.site().cameras) positions.push_back(camera.color_camera().position_in_site());
  IbrSettings settings = e.ibr;
  settings.width = options.width;
  settings.height = options.height;
  if (settings.supersample != 1) throw std::invalid_argument("export lumi: the network runs on unsupersampled portraits");
  settings.split_warp = true;  // the network's inputs are the per-view warps
  IbrRenderer renderer(context, simulator.renderer().camera_models(), settings);

  std::filesystem::create_directories(options.out);
  const uint32_t sw = passes::lumi_small_size(options.width, e.scale), sh = passes::lumi_small_size(options.height, e.scale);
  nlohmann::json index = {{"format", "remotetouch-lumi-export/1"},
                          {"scene", e.scene},
                          {"site", e.site},
                          {"width", options.width},
                          {"height", options.height},
                          {"scale", e.scale},
                          {"small_width", sw},
                          {"small_height", sh},
                          {"views", settings.views},
                          {"input_channels", {"red", "green", "blue", "coverage", "angle_rad", "resolution_m", "feather"}},
                          {"frames", nlohmann::json::array()}};
  std::printf("export lumi: scene %s, site %s, %ux%u at 1/%u (%ux%u), %u views, %u frames, on %s\n", e.scene.c_str(),
              e.site.c_str(), options.width, options.height, e.scale, sw, sh, settings.views, frames,
              context.device_name().c_str());
  for (uint32_t i = 0; i < frames; ++i) {
    simulator.seek(e.first_frame + uint64_t(i) * e.frame_step);
    const std::optional<sim::RgbdFrame> frame = simulator.next_frame();
    if (!frame) break;
    const sim::PersonPose& pose = simulator.last_pose();
    const auto selection = ibr::select_cameras(positions, ibr::touching_hand(pose.right_hand, pose.left_hand), settings.views);
    renderer.prepare(frame->cameras, selection, target);
    session.run_frame(renderer.graph(), i);
    // The graph knows its passes' outputs once it has run.
    vk::Image& warped = written_by(renderer.graph(), "ibr_warp", "ibr warped");
    vk::Image& features = written_by(renderer.graph(), "ibr_warp", "ibr features");
    const passes::LumiInputs in = passes::lumi_input_reference(vk::download(context, warped), vk::download(context, features),
                                                               options.height, settings.views, e.scale);
    const HostImage truth = simulator.renderer().target_color();
    const HostImage part = simulator.renderer().target_part();
    char name[32];
    std::snprintf(name, sizeof name, "frame_%04u.bin", uint32_t(frame->index));
    std::ofstream out(options.out / name, std::ios::binary);
    write_floats(out, in.inputs.values);
    write_floats(out, in.coverage.values);
    for (uint32_t c = 0; c < 4; ++c) write_floats(out, block_mean(truth, c, e.scale, [](float v) { return v; }));
    write_floats(out, block_mean(part, 0, e.scale, [](float v) { return v == float(RT_PART_HAND) ? 1.0f : 0.0f; }));
    if (!out) throw std::runtime_error("export lumi: cannot write " + (options.out / name).string());
    index["frames"].push_back(name);
    std::fprintf(stderr, "\r  frame %u/%u", i + 1, frames);
  }
  std::fprintf(stderr, "\n");
  std::ofstream(options.out / "index.json") << index.dump(2) << "\n";
  std::printf("wrote %zu frames to %s\n", index["frames"].size(), options.out.string().c_str());
  return 0;
}

}  // namespace rt::pipeline
