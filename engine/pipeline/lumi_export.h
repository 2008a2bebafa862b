#pragma once
// `remotetouch export lumi`: Lumi-Net's training data from the simulator. For each frame, the
// network's input tensors exactly as the GPU forward pass computes them (lumi_input from the
// image-based model's warped views) and the truth at the network's resolution.
#include <string>

#include "pipeline/ibr_settings.h"
#include "pipeline/run_options.h"

namespace rt::pipeline {

struct ExportLumiOptions {
  std::string scene = "miss";
  std::string site = "A";
  IbrSettings ibr;             // the image-based model up to the warp (its blending is not used)
  uint32_t scale = 2;          // the network's resolution: 1/scale of the target's
  uint32_t supersample = 3;    // the simulator's color supersampling, as eval ibr's default
  bool frames_given = false;
  uint32_t first_frame = 0;
  uint32_t frame_step = 1;
};

// Writes OUT/index.json and OUT/frame_NNNN.bin (format in lumi_export.cpp and scripts/train-lumi).
int run_export_lumi(const RunOptions& options, const ExportLumiOptions& exported);

}  // namespace rt::pipeline
