#pragma once
// The Vulkan context of one command, with RenderDoc attached first when a capture is asked for
// (RenderDoc must hook the instance at its creation).
#include <memory>
#include <optional>
#include <string>

#include "pipeline/run_options.h"
#include "vulkan/context.h"
#include "vulkan/frame_graph.h"
#include "vulkan/renderdoc_capture.h"

namespace rt::pipeline {

class GpuSession {
 public:
  explicit GpuSession(const RunOptions& options);
  vk::Context& context() { return *context_; }

  // Runs one frame of `graph`, capturing it if it is the requested frame.
  void run_frame(vk::FrameGraph& graph, uint32_t frame_index);
  // For work that is not one graph run: bracket it (no-ops without RenderDoc). end_capture
  // returns the capture's file, when one was written.
  void begin_capture(const std::string& title = "");
  std::optional<std::string> end_capture();
  bool capture_available() const { return capture_.available(); }
  const std::string& capture_unavailable_reason() const { return capture_.why_unavailable(); }
  // Says whether the requested capture was taken, and where, or why not.
  void report_capture() const;

 private:
  int capture_frame_;
  vk::RenderDocCapture capture_;
  std::unique_ptr<vk::Context> context_;
  std::optional<std::string> capture_path_;
};

std::string default_pipeline_cache_path();

// Writes every image the passes of `graph` wrote in its last run, as `folder/pass.image` EXR and
// 16-bit PNG (--dump-passes).
void dump_pass_outputs(vk::Context& context, const vk::FrameGraph& graph, const std::filesystem::path& folder);

}  // namespace rt::pipeline
