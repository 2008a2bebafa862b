#pragma once
// The configurations `bench accuracy` measures: points of the image-based model's accuracy
// against its time, each a setting of its knobs (pipeline/ibr_settings.h), of the cameras'
// resolution and of the portrait's size. A grid varies each of its axes alone around the
// defaults, then takes the full product of its most valuable few. CPU only.
#include <cstdint>
#include <string>
#include <vector>

#include "pipeline/ibr_settings.h"

namespace rt::pipeline {

struct AccuracyConfig {
  IbrSettings ibr;              // its width and height: the base size times portrait_scale
  double resolution_scale = 0;  // of the cameras; 0 = the scene's own
  double portrait_scale = 1;    // of the base portrait size, per axis
};

// The portrait size of `config` for a base size (never below 16 pixels an axis).
std::pair<uint32_t, uint32_t> portrait_size(const AccuracyConfig& config, uint32_t base_width, uint32_t base_height);

// The command-line words that set `config` over the defaults, e.g. "--views 6 --refine 9
// --resolution-scale 1" (size words only when the size differs from the base); empty for the
// defaults. A configuration's name in results.csv and pareto.md.
std::string accuracy_options(const AccuracyConfig& config, uint32_t base_width, uint32_t base_height);

struct GridAxis {
  std::string name;                 // a knob of ibr_knobs(), resolution-scale or portrait-scale
  std::vector<std::string> values;  // as command-line words; flags: on or off; resolution-scale: scene = its own
};

struct AccuracyGrid {
  std::string name;
  std::string summary;  // for --help
  std::vector<GridAxis> one_at_a_time;
  std::vector<GridAxis> product;  // every combination of these
};

const std::vector<AccuracyGrid>& accuracy_grids();  // tiny, small, full
// Throws std::invalid_argument listing the grids for an unknown name.
const AccuracyGrid& accuracy_grid(const std::string& name);

// Sets axis `name` of `config` to `word`; throws std::invalid_argument naming both and what is accepted.
void set_axis(AccuracyConfig& config, const std::string& name, const std::string& word);

// The defaults, each one-at-a-time value, then the product; a configuration met again is left out.
std::vector<AccuracyConfig> expand_grid(const AccuracyGrid& grid);

}  // namespace rt::pipeline
