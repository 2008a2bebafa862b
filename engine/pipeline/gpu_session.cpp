#include "pipeline/gpu_session.h"

#include <algorithm>
#include <cstdlib>
#include <iostream>

#include "image/image_io.h"

namespace rt::pipeline {

std::string default_pipeline_cache_path() {
  if (const char* cache = std::getenv("XDG_CACHE_HOME"); cache && *cache)
    return std::string(cache) + "/remotetouch/pipelines.bin";
  if (const char* home = std::getenv("HOME"); home && *home) return std::string(home) + "/.cache/remotetouch/pipelines.bin";
  return {};
}

GpuSession::GpuSession(const RunOptions& options)
    : capture_frame_(options.capture_frame),
      capture_(options.capture_frame >= 0, (options.out / "capture" / "remotetouch").string()) {
  vk::ContextOptions context_options;
  context_options.device_name = options.device;
  context_options.validation = options.validation;
  context_options.pipeline_cache_path = default_pipeline_cache_path();
  context_options.surface_instance_extensions = options.surface_instance_extensions;
  context_options.presentation = options.presentation;
  context_ = std::make_unique<vk::Context>(vk::apply_environment(context_options));
}

void GpuSession::run_frame(vk::FrameGraph& graph, uint32_t frame_index) {
  const bool capture = capture_frame_ == int(frame_index);
  if (capture) begin_capture();
  graph.run();
  if (capture) end_capture();
}

void GpuSession::begin_capture(const std::string& title) {
  if (capture_.available()) capture_.begin_frame(context_->instance(), title);
}

std::optional<std::string> GpuSession::end_capture() {
  if (capture_.available()) capture_path_ = capture_.end_frame(context_->instance());
  return capture_path_;
}

void GpuSession::report_capture() const {
  if (capture_frame_ < 0) return;
  if (capture_path_) std::cout << "RenderDoc capture of frame " << capture_frame_ << ": " << *capture_path_ << "\n";
  else if (!capture_.available()) std::cout << "no capture taken: " << capture_.why_unavailable() << "\n";
  else std::cout << "no capture taken: frame " << capture_frame_ << " was never run\n";
}

// Every image each pass of `graph` wrote, as EXR (exact) and 16-bit PNG, named pass.image.
void dump_pass_outputs(vk::Context& context, const vk::FrameGraph& graph, const std::filesystem::path& folder) {
  for (const auto& [pass, image] : graph.written_images()) {
    const HostImage pixels = vk::download(context, *image);
    // No spaces in file names: "ibr_carve.ibr_carved_depth", not "ibr_carve.ibr carved depth".
    std::string name = pass + "." + image->name();
    std::replace(name.begin(), name.end(), ' ', '_');
    const std::filesystem::path stem = folder / name;
    write_image(stem.string() + ".exr", pixels);
    write_image(stem.string() + ".png", pixels, PngDepth::Sixteen);
  }
}

}  // namespace rt::pipeline
