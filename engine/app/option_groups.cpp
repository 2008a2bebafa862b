#include "app/option_groups.h"

#include "config/json.h"
#include "pipeline/quality.h"

namespace rt::app {

void add_run_options(CLI::App& command, RunOptions& options, const std::string& default_out) {
  options.out = default_out;
  command.add_option("--out", options.out, "Output directory")->capture_default_str();
  command.add_option("--device", options.device,
                     "Vulkan device: a part of its name (e.g. llvmpipe, NVIDIA); default prefers a GPU "
                     "(or REMOTETOUCH_DEVICE)");
  command.add_flag("--validation", options.validation, "Enable the Khronos validation layer; errors fail the run");
}

CLI::Option* add_frames_option(CLI::App& command, RunOptions& options, uint32_t default_frames,
                               const std::string& default_text) {
  options.frames = default_frames;
  CLI::Option* frames = command.add_option("--frames", options.frames, "Frames to render")->check(CLI::Range(1u, 1000000u));
  if (default_text.empty())
    frames->capture_default_str();
  else
    frames->default_str(default_text);
  return frames;
}

void add_inspection_options(CLI::App& command, RunOptions& options) {
  command.add_flag("--profile", options.profile, "Print per-pass GPU times (median over the frames)");
  command.add_option("--capture-frame", options.capture_frame,
                     "Capture this frame (0-based) with RenderDoc, when RenderDoc is present")
      ->check(CLI::NonNegativeNumber);
}

void check_capture_frame(const RunOptions& options) {
  if (options.capture_frame >= int(options.frames))
    throw CLI::ValidationError("--capture-frame", "frame " + std::to_string(options.capture_frame) +
                                                      " is past the last frame (--frames " +
                                                      std::to_string(options.frames) + " renders 0.." +
                                                      std::to_string(options.frames - 1) + ")");
}

void add_size_options(CLI::App& command, RunOptions& options, const std::string& what, uint32_t low, uint32_t high,
                      bool optional) {
  CLI::Option* width = command.add_option("--width", options.width, what + " width")->check(CLI::Range(low, high));
  CLI::Option* height = command.add_option("--height", options.height, what + " height")->check(CLI::Range(low, high));
  if (optional) {
    width->needs(height);
    height->needs(width);
  } else {
    width->capture_default_str();
    height->capture_default_str();
  }
}

void QualityOptions::add_to(CLI::App& command) {
  preset_ = command
                .add_option("--quality", preset_name_,
                            "Image-based model preset from bench accuracy's front (assets/quality/presets.json): fast, "
                            "balanced, best; the model's options given still apply over it")
                ->group("Image-based model");
  budget_ = command
                .add_option("--budget-ms", budget_ms_,
                            "The most accurate configuration measured (--budget-results) that takes at most this many "
                            "GPU ms a frame at this portrait size")
                ->check(CLI::PositiveNumber)
                ->excludes(preset_)
                ->group("Image-based model");
  command.add_option("--budget-results", results_, "results.csv of bench accuracy for --budget-ms")
      ->capture_default_str()
      ->needs(budget_)
      ->group("Image-based model");
}

nlohmann::json QualityOptions::apply(pipeline::IbrSettings& ibr, double& resolution_scale,
                                     bool resolution_scale_given) const {
  if (!chosen()) return nullptr;
  pipeline::QualityChoice choice;
  try {
    choice = preset_->count() > 0 ? pipeline::quality_preset(preset_name_, ibr)
                                  : pipeline::quality_within_budget(results_, budget_ms_, ibr);
  } catch (const std::exception& error) {
    throw CLI::ValidationError(preset_->count() > 0 ? "--quality" : "--budget-ms", error.what());
  }
  ibr = choice.ibr;
  if (!resolution_scale_given && choice.resolution_scale > 0) resolution_scale = choice.resolution_scale;
  return choice.description;
}

std::vector<std::string> QualityOptions::arguments() const {
  if (preset_->count() > 0) return {"--quality", preset_name_};
  if (budget_->count() > 0) return {"--budget-ms", config::format_number(budget_ms_), "--budget-results", results_.string()};
  return {};
}

IbrOptions add_ibr_options(CLI::App& command, const std::vector<std::string>& skip) {
  return IbrOptions(command, pipeline::ibr_knobs(), pipeline::IbrSettings{}, "Image-based model", "", skip);
}

HandOptions add_hand_options(CLI::App& command) {
  return HandOptions(command, pipeline::hand_knobs(), pipeline::HandRendererOptions{}, "Geometry hand",
                     pipeline::kHandOptionPrefix);
}

TouchOptions add_touch_options(CLI::App& command) { return TouchOptions(command, touch_knobs(), TouchSettings{}, "Touch"); }

}  // namespace rt::app
