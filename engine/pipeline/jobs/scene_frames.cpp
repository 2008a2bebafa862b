#include "pipeline/jobs.h"

#include <stdexcept>

namespace rt::pipeline {

uint32_t select_scene_frames(sim::Scene& scene, const FrameSelection& selection, const std::string& command) {
  if (selection.frame_step == 0) throw std::invalid_argument(command + ": --frame-step must be at least 1");
  if (selection.first_frame >= scene.frame_count)
    throw std::invalid_argument(command + ": --first-frame " + std::to_string(selection.first_frame) + " is past the scene's " +
                                std::to_string(scene.frame_count) + " frames");
  const uint32_t frames = selection.frames ? *selection.frames
                                           : (scene.frame_count - selection.first_frame + selection.frame_step - 1) / selection.frame_step;
  if (frames == 0) throw std::invalid_argument(command + ": --frames must be at least 1");
  scene.frame_count = selection.first_frame + (frames - 1) * selection.frame_step + 1;
  return frames;
}

}  // namespace rt::pipeline
