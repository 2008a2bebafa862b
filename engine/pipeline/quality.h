#pragma once
// Named points of the image-based model's accuracy-against-time trade-off for the commands that
// render with it (--quality fast|balanced|best, from assets/quality/presets.json, picked on the
// front that `bench accuracy` drew), and the most accurate configuration a results.csv measured
// within a GPU time budget (--budget-ms). Either gives the model's knobs and the cameras'
// resolution scale; the knobs given on the command line still apply over them. CPU only.
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "pipeline/ibr_settings.h"

namespace rt::pipeline {

struct QualityChoice {
  IbrSettings ibr;
  double resolution_scale = 0;  // of the cameras; 0 = the scene's own
  nlohmann::json description;   // for metrics files: what was chosen, from where, with which options
};

std::filesystem::path quality_presets_path();  // assets/quality/presets.json
std::vector<std::string> quality_preset_names();
// `base`'s knobs under those the preset names. Throws naming the file and the preset.
QualityChoice quality_preset(const std::string& name, const IbrSettings& base);
// The most accurate row of `results` (a results.csv of bench accuracy) measured at this portrait
// size within `budget_ms`; its knobs replace all of `base`'s. Throws saying why none fits.
QualityChoice quality_within_budget(const std::filesystem::path& results, double budget_ms, const IbrSettings& base);

}  // namespace rt::pipeline
