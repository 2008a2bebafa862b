#pragma once
// An appearance-adaption state from an earlier frame (one frame of statistics), for the tests that
// check how a new frame is smoothed into it.
#include "passes/hand_color_reduce.h"

namespace rt::test {

inline passes::AppearanceState previous_appearance_state() {
  passes::AppearanceState previous{};
  previous.header = {1.0f, 4.0f, 0.0f, 0.0f};
  previous.image_mean = {-0.5f, 0.05f, 0.01f, 0.0f};
  previous.image_sigma = {0.1f, 0.02f, 0.02f, 0.0f};
  previous.mesh_mean = {-0.4f, 0.04f, 0.02f, 0.0f};
  previous.mesh_sigma = {0.05f, 0.01f, 0.01f, 0.0f};
  return previous;
}

}  // namespace rt::test
