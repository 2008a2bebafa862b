#pragma once
// The option groups the commands share, each declared once:
//   run:    --out (the command's default), --device, --validation: every command that uses the GPU
//   frames: --frames (with what its default is), and for a command that renders its frames in
//           this process --profile and --capture-frame (checked against --frames)
//   size:   --width and --height
//   image-based model: the knobs of pipeline/ibr_settings.h (--views, --fusion, --carve, ...)
//   hand:   the knobs of pipeline/hand_settings.h (--hand-min-confidence, ...)
//   touch:  the knobs of touch/touch_settings.h (--contact-prediction, --motor-latency-ms)
//   quality: --quality PRESET or --budget-ms M (pipeline/quality.h), under the image-based model's
//           options given
#include <CLI/CLI.hpp>

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "app/options.h"
#include "config/knobs.h"
#include "pipeline/hand_settings.h"
#include "pipeline/ibr_settings.h"
#include "touch/touch_settings.h"

namespace rt::app {

void add_run_options(CLI::App& command, RunOptions& options, const std::string& default_out);

// --frames; `default_text` says what the default is when it is not a plain number ("the scene's
// own count"); then options.frames is the value used only when --frames is given.
CLI::Option* add_frames_option(CLI::App& command, RunOptions& options, uint32_t default_frames,
                               const std::string& default_text = "");
// --profile and --capture-frame; check_capture_frame after parsing.
void add_inspection_options(CLI::App& command, RunOptions& options);
// Throws CLI::ValidationError when --capture-frame is past the last of options.frames.
void check_capture_frame(const RunOptions& options);

// --width and --height with their defaults in options and a range; `optional`: neither has a
// default, and either needs the other.
void add_size_options(CLI::App& command, RunOptions& options, const std::string& what, uint32_t low, uint32_t high,
                      bool optional = false);

// A knob table bound to a command's options: `prefix` before each name, knobs named in `skip` left
// out (a command with its own version of one). Keep the object alive until after parsing.
template <class Settings>
class KnobOptions {
 public:
  KnobOptions() = default;
  KnobOptions(CLI::App& command, const config::KnobTable<Settings>& table, const Settings& defaults,
              const std::string& group, const std::string& prefix = "", const std::vector<std::string>& skip = {}) {
    for (const auto& knob : table) {
      bool skipped = false;
      for (const auto& name : skip) skipped = skipped || name == knob.name;
      if (skipped) continue;
      auto slot = std::make_unique<Slot>();
      slot->knob = &knob;
      const std::string name = "--" + prefix + knob.name;
      const std::string value = config::knob_word(knob, defaults);
      switch (knob.kind) {
        case config::KnobKind::Flag: slot->option = command.add_flag(name, slot->flag, knob.help); break;
        case config::KnobKind::Integer:
          slot->option = command.add_option(name, slot->integer, knob.help)
                             ->check(CLI::Range(int64_t(knob.low), int64_t(knob.high)))
                             ->default_str(value);
          break;
        case config::KnobKind::Real:
          slot->option = command.add_option(name, slot->real, knob.help)
                             ->check(CLI::Range(knob.low, knob.high))
                             ->default_str(value);
          break;
        case config::KnobKind::Choice:
          slot->option = command.add_option(name, slot->choice, knob.help)
                             ->check(CLI::IsMember(knob.choices))
                             ->default_str(value);
          break;
        case config::KnobKind::Text:
          slot->option = command.add_option(name, slot->text, knob.help)
                             ->check(CLI::Validator([](std::string& word) { return word.empty() ? "empty" : ""; }, ""))
                             ->default_str(value);
          break;
      }
      slot->option->group(group);
      slots_.push_back(std::move(slot));
    }
  }

  // The options given on the command line, over `settings` (a config's, or the defaults).
  void apply(Settings& settings) const {
    for (const auto& slot : slots_) {
      if (slot->option->count() == 0) continue;
      const auto& knob = *slot->knob;
      switch (knob.kind) {
        case config::KnobKind::Flag: knob.set(settings, slot->flag ? 1 : 0); break;
        case config::KnobKind::Integer: knob.set(settings, double(slot->integer)); break;
        case config::KnobKind::Real: knob.set(settings, slot->real); break;
        case config::KnobKind::Choice:
          for (size_t i = 0; i < knob.choices.size(); ++i)
            if (knob.choices[i] == slot->choice) knob.set(settings, double(i));
          break;
        case config::KnobKind::Text: knob.set_text(settings, slot->text); break;
      }
    }
  }

  CLI::Option* option(const std::string& knob_name) const {
    for (const auto& slot : slots_)
      if (slot->knob->name == knob_name) return slot->option;
    return nullptr;
  }
  bool given(const std::string& knob_name) const {
    const CLI::Option* found = option(knob_name);
    return found && found->count() > 0;
  }

 private:
  struct Slot {
    const config::Knob<Settings>* knob = nullptr;
    CLI::Option* option = nullptr;
    bool flag = false;
    int64_t integer = 0;
    double real = 0;
    std::string choice, text;
  };
  std::vector<std::unique_ptr<Slot>> slots_;
};

using IbrOptions = KnobOptions<pipeline::IbrSettings>;
using HandOptions = KnobOptions<pipeline::HandRendererOptions>;
using TouchOptions = KnobOptions<TouchSettings>;

// --quality PRESET, or --budget-ms M with --budget-results FILE: the image-based model's knobs
// and the cameras' resolution scale from a point of `bench accuracy`'s front. Keep the object
// alive until after parsing (the options write into it).
class QualityOptions {
 public:
  void add_to(CLI::App& command);
  bool chosen() const { return preset_->count() > 0 || budget_->count() > 0; }
  // The choice over `ibr` (whose width and height must be the portrait's) and, unless
  // --resolution-scale was given, over `resolution_scale`; apply the knobs given afterwards.
  // Returns what was chosen, for metrics (null without a choice). Throws CLI::ValidationError
  // saying what is wrong with the preset or the results file.
  nlohmann::json apply(pipeline::IbrSettings& ibr, double& resolution_scale, bool resolution_scale_given) const;
  // The words that give a child process the same choice.
  std::vector<std::string> arguments() const;

 private:
  std::string preset_name_;
  double budget_ms_ = 0;
  std::filesystem::path results_ = "out/bench-accuracy/results.csv";
  CLI::Option* preset_ = nullptr;
  CLI::Option* budget_ = nullptr;
};

// The image-based model's options (all of pipeline::ibr_knobs() but those in `skip`).
IbrOptions add_ibr_options(CLI::App& command, const std::vector<std::string>& skip = {});
// The geometry hand's options, --hand-NAME.
HandOptions add_hand_options(CLI::App& command);
// The site's touch options (--contact-prediction, --motor-latency-ms).
TouchOptions add_touch_options(CLI::App& command);

}  // namespace rt::app
