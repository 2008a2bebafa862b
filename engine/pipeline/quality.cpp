#include "pipeline/quality.h"

#include "config/assets.h"
#include "config/json.h"
#include "pipeline/accuracy_results.h"

namespace rt::pipeline {

namespace {

const nlohmann::json& presets_object(const nlohmann::json& file, const std::filesystem::path& path) {
  return config::require_object(file, "presets", path.string());
}

}  // namespace

std::filesystem::path quality_presets_path() { return config::assets_dir() / "quality" / "presets.json"; }

std::vector<std::string> quality_preset_names() {
  const std::filesystem::path path = quality_presets_path();
  const nlohmann::json file = config::read_json_file(path);
  std::vector<std::string> names;
  for (const auto& [name, preset] : presets_object(file, path).items()) names.push_back(name);
  return names;
}

QualityChoice quality_preset(const std::string& name, const IbrSettings& base) {
  const std::filesystem::path path = quality_presets_path();
  const nlohmann::json file = config::read_json_file(path);
  const nlohmann::json& presets = presets_object(file, path);
  if (!presets.contains(name)) {
    std::string known;
    for (const auto& [key, preset] : presets.items()) known += (known.empty() ? "" : ", ") + key;
    throw config::JsonError(path.string() + ": no preset '" + name + "' (known: " + known + ")");
  }
  const nlohmann::json& preset = presets[name];
  const std::string where = path.string() + ": preset '" + name + "'";
  config::reject_unknown_fields(preset, {"ibr", "resolution_scale", "why"}, where);
  QualityChoice choice;
  choice.ibr = base;
  if (preset.contains("ibr")) config::read_knobs_json(ibr_knobs(), preset["ibr"], choice.ibr, where + ": 'ibr'");
  if (preset.contains("resolution_scale"))
    choice.resolution_scale = config::require_in_range(preset, "resolution_scale", where, 0.01, 1.0);
  choice.description = {{"preset", name}, {"file", path.string()}, {"ibr", ibr_settings_json(choice.ibr)},
                        {"resolution_scale", choice.resolution_scale > 0 ? nlohmann::json(choice.resolution_scale)
                                                                         : nlohmann::json("the scene's")}};
  if (preset.contains("why")) choice.description["why"] = preset["why"];
  if (file.contains("measured_by")) choice.description["measured_by"] = file["measured_by"];
  return choice;
}

QualityChoice quality_within_budget(const std::filesystem::path& results, double budget_ms, const IbrSettings& base) {
  const std::vector<AccuracyRow> rows = read_accuracy_csv(results);
  const AccuracyRow& row =
      most_accurate_within(rows, budget_ms, base.width, base.height, "--budget-ms with " + results.string());
  QualityChoice choice;
  choice.ibr = row.ibr;
  choice.ibr.width = base.width;
  choice.ibr.height = base.height;
  choice.resolution_scale = row.resolution_scale;
  choice.description = {{"budget_ms", budget_ms},
                        {"results", results.string()},
                        {"options", row.options},
                        {"measured_gpu_ms", row.gpu_ms},
                        {"measured_psnr_fg_db", row.psnr_fg_db},
                        {"measured_scenes", row.scenes},
                        {"ibr", ibr_settings_json(choice.ibr)},
                        {"resolution_scale", choice.resolution_scale}};
  return choice;
}

}  // namespace rt::pipeline
