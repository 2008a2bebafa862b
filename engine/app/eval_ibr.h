#pragma once
// `remotetouch eval ibr`: the image-based model against the simulator's ground truth.
#include <string>
#include <vector>

#include "app/options.h"
#include "pipeline/ibr_settings.h"

namespace rt::app {

struct EvalIbrOptions {
  std::string scene = "wave";
  std::string fusion = "min";  // min, avg, or both (each frame rendered with both, compared)
  std::string site = "A";      // whose user is rendered, for the other site's eye
  std::vector<std::string> cameras;  // a fixed selection by name; empty = opposite the touching hand
  // The image-based model (--views, --carve, --refine, ...); its fusion is set from `fusion`.
  pipeline::IbrSettings ibr;
  uint32_t supersample = 3;    // the simulator's color supersampling (scene's own is overridden)
  double resolution_scale = 0; // of the cameras' resolutions; 0 = the scene's own
  bool frames_given = false;   // else the scene's own frame count
  uint32_t first_frame = 0;    // of the scene: where the run starts
  uint32_t frame_step = 1;     // every Nth frame from there: a whole scene's motion at 1/N of the time
};


}  // namespace rt::app
