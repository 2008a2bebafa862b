#include "pipeline/hand_settings.h"

#include <cmath>

namespace rt::pipeline {

using config::KnobKind;

const config::KnobTable<HandRendererOptions>& hand_knobs() {
  using O = HandRendererOptions;
  static const config::KnobTable<O> table = {
      {"min-confidence", "Hand tracked below this tracker confidence counts as not tracked (no appearance adaption)",
       KnobKind::Real, 0, 1, {}, [](const O& o) { return double(o.min_confidence); },
       [](O& o, double v) { o.min_confidence = float(v); }},
      {"shape-adaption", "Shape adaption: the mesh fitted to the user's hand at the first well-tracked frame",
       KnobKind::Choice, 0, 0, {"on", "off"}, [](const O& o) { return o.shape_adaption ? 0.0 : 1.0; },
       [](O& o, double v) { o.shape_adaption = v == 0; }},
      {"shape-adaption-confidence", "The first frame with at least this tracker confidence fixes the hand's shape",
       KnobKind::Real, 0, 1, {}, [](const O& o) { return double(o.shape_adaption_confidence); },
       [](O& o, double v) { o.shape_adaption_confidence = float(v); }},
      {"appearance-smoothing",
       "Appearance adaption: least weight of a new frame's color statistics (the first 1/this frames are averaged)",
       KnobKind::Real, 0, 1, {}, [](const O& o) { return double(o.appearance_smoothing); },
       [](O& o, double v) { o.appearance_smoothing = float(v); }},
      {"appearance-stale-frames",
       "Appearance adaption: displayed frames without a fitting frame before the fit is reported stale", KnobKind::Integer,
       1, 1e7, {}, [](const O& o) { return double(o.appearance_stale_frames); },
       [](O& o, double v) { o.appearance_stale_frames = uint64_t(std::llround(v)); }},
      {"appearance-max-contrast",
       "Appearance adaption: the most the template's texture detail is stretched (cap on sigma_i / sigma_g of Eq. 3)",
       KnobKind::Real, 0.1, 20, {}, [](const O& o) { return double(o.appearance_max_contrast); },
       [](O& o, double v) { o.appearance_max_contrast = float(v); }},
      {"appearance-shading",
       "Appearance adaption: shade the mesh with the light estimated from the portrait (off: the albedo, unlit)",
       KnobKind::Choice, 0, 0, {"on", "off"}, [](const O& o) { return o.appearance_shading ? 0.0 : 1.0; },
       [](O& o, double v) { o.appearance_shading = v == 0; }},
      {"min-region-fraction",
       "Appearance adaption: least share of the image the hand must cover (and at least 16 pixels)", KnobKind::Real, 0,
       0.1, {}, [](const O& o) { return o.min_region_fraction; }, [](O& o, double v) { o.min_region_fraction = v; }},
      {"supersampling",
       "Samples a side of each displayed pixel of the hand (1 to 4): its silhouette antialiased against the portrait",
       KnobKind::Integer, 1, 4, {}, [](const O& o) { return double(o.supersampling); },
       [](O& o, double v) { o.supersampling = uint32_t(std::llround(v)); }},
  };
  return table;
}

nlohmann::json hand_settings_json(const HandRendererOptions& options) { return config::knobs_to_json(hand_knobs(), options); }

}  // namespace rt::pipeline
