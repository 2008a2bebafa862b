// The command line of bench accuracy; the work itself is pipeline/jobs/bench_accuracy.cpp.
#include <nlohmann/json.hpp>

#include "app/command.h"
#include "app/option_groups.h"
#include "pipeline/accuracy_grid.h"
#include "pipeline/jobs.h"

namespace rt::app {

using namespace rt::pipeline;

namespace {

class BenchAccuracyCommand : public Command {
 public:
  CLI::App* add_to(CLI::App& parent) override {
    std::vector<std::string> grids;
    std::string grid_help = "Which configurations:";
    for (const AccuracyGrid& grid : accuracy_grids()) {
      grids.push_back(grid.name);
      grid_help += " " + grid.name + " (" + std::to_string(expand_grid(grid).size()) + ": " + grid.summary + ");";
    }
    grid_help.pop_back();
    CLI::App* command = parent.add_subcommand(
        "accuracy",
        "The image-based model's accuracy against its GPU time over a grid of its knobs, camera resolution and portrait "
        "size: OUT/results.csv, OUT/pareto.md (the front), OUT/pareto.png; resumes a stopped run in the same OUT");
    command->add_option("--scenes", bench_.scenes, "Scenes under assets/scenes/ (or scene files), comma-separated")
        ->delimiter(',')
        ->capture_default_str();
    command->add_option("--grid", bench_.grid, grid_help)->check(CLI::IsMember(grids))->capture_default_str();
    command->add_option("--frame-step", bench_.frame_step, "Every Nth frame of each scene's motion")
        ->check(CLI::Range(1u, 1000u))
        ->capture_default_str();
    command->add_option("--supersample", bench_.supersample,
                        "Simulated color and ground truth rendered at N x N samples per pixel, box-filtered (odd)")
        ->check(CLI::IsMember({1u, 3u, 5u, 7u}))
        ->capture_default_str();
    command->add_flag("--no-plot", no_plot_, "Skip pareto.png (it needs python3-matplotlib)");
    add_run_options(*command, options_, "out/bench-accuracy");
    frames_ = add_frames_option(*command, options_, 1, "each scene's whole motion at --frame-step");
    frames_->description("Frames of each scene");
    options_.width = 640;
    options_.height = 360;
    add_size_options(*command, options_, "Base portrait", 16, 4096);
    return command;
  }
  void check() override {
    bench_.frames_given = frames_->count() > 0;
    bench_.plot = !no_plot_;
    if (bench_.scenes.empty()) throw CLI::ValidationError("--scenes", "names no scene");
  }
  int run() override { return run_bench_accuracy(options_, bench_); }

 private:
  RunOptions options_;
  BenchAccuracyOptions bench_;
  CLI::Option* frames_ = nullptr;
  bool no_plot_ = false;
};

}  // namespace

std::unique_ptr<Command> make_bench_accuracy_command() { return std::make_unique<BenchAccuracyCommand>(); }

}  // namespace rt::app
