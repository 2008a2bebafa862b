#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "app/options.h"
#include "geometry/site_frames.h"
#include "vulkan/frame_graph.h"

namespace rt::app {


struct SimulateOptions {
  std::string scene = "clap";  // a name under assets/scenes/, or a path to a scene file
  Site site = Site::A;
  bool frames_given = false;   // --frames overrides the scene's frame count
  uint32_t gt_width = 640, gt_height = 360;  // the ground-truth target view
  double resolution_scale = 0.0;             // of the cameras; 0 = the scene's own
};

int run_simulate(const RunOptions& options, const SimulateOptions& simulate);

}  // namespace rt::app
