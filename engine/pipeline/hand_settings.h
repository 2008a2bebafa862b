#pragma once
// The geometry hand's user-settable knobs (HandRendererOptions, used by hand_renderer.h) as
// one table (config/knobs.h): the command-line options --hand-NAME, a site config's "hand"
// object (keys without the prefix) and what a parent forwards to a child. A new knob is one field
// of HandRendererOptions plus one row in hand_knobs() (hand_settings.cpp).
#include <nlohmann/json.hpp>

#include "config/knobs.h"

namespace rt::pipeline {

struct HandRendererOptions {
  float min_confidence = 0.5f;              // below: not tracked (no appearance adaption)
  float shape_adaption_confidence = 0.8f;   // the first frame at least this good fixes the shape
  bool shape_adaption = true;
  float appearance_smoothing = 0.25f;       // least weight of a new frame's statistics (running mean before)
  uint64_t appearance_stale_frames = 300;   // displayed frames without a fit before it counts as stale
  float appearance_max_contrast = 1.5f;     // cap on sigma_i / sigma_g (passes/hand_color_transfer.h)
  bool appearance_shading = true;           // shade the mesh with the light estimated from the portrait
  double min_region_fraction = 2e-4;        // of the image, and at least 16 pixels
  uint32_t supersampling = 2;               // samples a side of each displayed pixel (1 to 4)
};

// min-confidence, shape-adaption-confidence, shape-adaption (on|off), appearance-smoothing,
// appearance-stale-frames, appearance-max-contrast, appearance-shading (on|off), min-region-fraction,
// supersampling.
const config::KnobTable<HandRendererOptions>& hand_knobs();
// The prefix of the hand's command-line options: --hand-min-confidence.
inline constexpr const char* kHandOptionPrefix = "hand-";

// Every knob of `options` as JSON (keys as in a site config's "hand" object), for metrics files.
nlohmann::json hand_settings_json(const HandRendererOptions& options);

}  // namespace rt::pipeline
