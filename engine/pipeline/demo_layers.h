#pragma once
// Generated stand-ins for the layers the compositing passes will receive once the image-based
// portrait and the geometry hand exist: a striped upper body, a skin-colored hand with its
// mask, and a background. Smooth edges, so that blending errors would show.
#include "image/host_image.h"

namespace rt::pipeline {

struct DemoLayers {
  HostImage portrait;    // rgba32f, straight alpha
  HostImage hand_color;  // rgba32f
  HostImage hand_mask;   // r32f coverage
  HostImage background;  // rgba32f
};

DemoLayers make_demo_layers(uint32_t width, uint32_t height);

// Hand distance to the screen over the demo: approach from 0.5 m, touch (5 cm), retract.
float demo_hand_distance_m(uint32_t frame, uint32_t frame_count);

}  // namespace rt::pipeline
