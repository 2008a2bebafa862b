#pragma once
// What the benchmarks (`remotetouch bench KIND`, one file each) share: the run options, --frames
// (20 unless the benchmark says), --profile and --capture-frame, and --width/--height for those that sweep sizes.
#include <string>

#include "app/command.h"
#include "app/option_groups.h"

namespace rt::app {

class BenchCommand : public Command {
 public:
  // `sizes`: the sizes it runs by default, e.g. "1280x720 and 2560x1440"; empty: it takes no size.
  // `default_frames`: --frames when not given.
  BenchCommand(std::string name, std::string help, std::string frames_help, std::string sizes = "", uint32_t default_frames = 20)
      : name_(std::move(name)), help_(std::move(help)), frames_help_(std::move(frames_help)), sizes_(std::move(sizes)),
        default_frames_(default_frames) {}

  CLI::App* add_to(CLI::App& parent) override {
    CLI::App* command = parent.add_subcommand(name_, help_);
    add_run_options(*command, options_, "out/bench");
    add_frames_option(*command, options_, default_frames_)->description(frames_help_);
    add_inspection_options(*command, options_);
    if (!sizes_.empty()) {
      add_size_options(*command, options_, "Only this", 1, 16384, true);
      command->get_option("--width")->description("Only this width (default: " + sizes_ + ")");
    }
    add_options(*command);
    return command;
  }
  void check() override { check_capture_frame(options_); }

 protected:
  virtual void add_options(CLI::App&) {}
  RunOptions options_;

 private:
  std::string name_, help_, frames_help_, sizes_;
  uint32_t default_frames_ = 20;
};

}  // namespace rt::app
