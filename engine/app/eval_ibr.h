#pragma once
// `remotetouch eval ibr`: the image-based model against the simulator's ground truth.
#include <string>
#include <vector>

#include "app/options.h"
#include "passes/ibr_blend.h"
#include "passes/ibr_splat.h"

namespace rt::app {

struct EvalIbrOptions {
  std::string scene = "wave";
  std::string fusion = "min";  // min, avg, or both (each frame rendered with both, compared)
  std::string site = "A";      // whose user is rendered, for the other site's eye
  uint32_t views = 4;
  std::vector<std::string> cameras;  // a fixed selection by name; empty = opposite the touching hand
  bool carve = false;          // see-through carving of the fused depth
  int refine_hypotheses = 0;   // plane-sweep refinement; 0 = off
  int best_views = passes::BlendSettings{}.best_views;  // k of the blending; the pass's own default
  // avg fusion: depths this far behind the nearest join the mean; the pass's own default
  float average_tolerance_m = passes::SplatSettings{}.average_tolerance_m;
  float edge_inset_depth_px = passes::SplatSettings{}.edge_inset;  // of a depth pixel; the pass's own default
  uint32_t supersample = 3;    // the simulator's color supersampling (scene's own is overridden)
  double resolution_scale = 0; // of the cameras' resolutions; 0 = the scene's own
  uint32_t portrait_supersample = 1;  // the portrait rendered at N x N samples per pixel and resolved
  bool frames_given = false;   // else the scene's own frame count
  uint32_t first_frame = 0;    // of the scene: where the run starts
  uint32_t frame_step = 1;     // every Nth frame from there: a whole scene's motion at 1/N of the time
};

int run_eval_ibr(const RunOptions& options, const EvalIbrOptions& eval);

}  // namespace rt::app
