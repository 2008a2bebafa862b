// The command line of eval ibr; the work itself is pipeline/jobs/eval_ibr.cpp.
#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "app/command.h"
#include "app/option_groups.h"
#include "pipeline/jobs.h"

namespace rt::app {

using namespace rt::pipeline;

namespace {

class EvalIbrCommand : public Command {
 public:
  CLI::App* add_to(CLI::App& parent) override {
    CLI::App* command = command_ = parent.add_subcommand(
        "ibr", "The image-based model (fusion, warping, blending) against ground truth: metrics.json, PNGs, a table");
    command->add_option("--scene", eval_.scene, "Scene name under assets/scenes/, or a scene file")->capture_default_str();
    // Its own --fusion: both renders every frame with each and compares them.
    command->add_option("--fusion", eval_.fusion, "Depth fusion: min (the paper), avg (baseline), both")
        ->check(CLI::IsMember({"min", "avg", "both"}))
        ->capture_default_str()
        ->group("Image-based model");
    ibr_ = add_ibr_options(*command, {"fusion"});
    quality_.add_to(*command);
    command
        ->add_option("--cameras", eval_.cameras,
                     "These cameras (site names, comma-separated) in every frame, instead of the ones opposite the "
                     "touching hand")
        ->delimiter(',')
        ->excludes(ibr_.option("views"));
    command->add_option("--supersample", eval_.supersample,
                        "Simulated color and ground truth rendered at N x N samples per pixel, box-filtered (odd)")
        ->check(CLI::IsMember({1u, 3u, 5u, 7u}))
        ->capture_default_str();
    command->add_option("--resolution-scale", eval_.resolution_scale, "Camera resolution scale (1 is the site's own)")
        ->check(CLI::Range(0.01, 1.0))
        ->default_str("the scene's");
    command->add_option("--cameras-from", eval_.cameras_from,
                        "The cameras' images from this recording of the same scene and site (simulate's output: "
                        "RemoteTouch's format or --format k4a) instead of the simulator's; the rest is as without")
        ->check(CLI::ExistingDirectory);
    command->add_flag("--dump-passes", options_.dump_passes,
                      "Write every pass output of the last frame (EXR and PNG) to OUT/passes/FUSION/");
    command->add_option("--first-frame", eval_.first_frame, "Scene frame to start at")
        ->check(CLI::Range(0u, 1000000u))
        ->capture_default_str();
    command->add_option("--frame-step", eval_.frame_step, "Render every Nth scene frame (the whole motion at 1/N of the time)")
        ->check(CLI::Range(1u, 1000u))
        ->capture_default_str();
    command->add_option("--site", eval_.site, "Whose user is rendered")->check(CLI::IsMember({"A", "B"}))->capture_default_str();
    add_run_options(*command, options_, "out/eval-ibr");
    frames_ = add_frames_option(*command, options_, 1, "the rest of the scene from --first-frame at --frame-step");
    add_inspection_options(*command, options_);
    options_.width = 640;
    options_.height = 360;
    add_size_options(*command, options_, "Target view", 1, 16384);
    return command;
  }
  void check() override {
    eval_.frames_given = frames_->count() > 0;
    if (eval_.frames_given) check_capture_frame(options_);
    eval_.ibr.width = options_.width;
    eval_.ibr.height = options_.height;
    eval_.quality = quality_.apply(eval_.ibr, eval_.resolution_scale, command_->count("--resolution-scale") > 0);
    // A chosen configuration's fusion, unless --fusion says otherwise.
    if (quality_.chosen() && command_->count("--fusion") == 0)
      eval_.fusion = eval_.ibr.fusion == passes::DepthFusion::Min ? "min" : "avg";
    ibr_.apply(eval_.ibr);
  }
  int run() override { return run_eval_ibr(options_, eval_); }

 private:
  RunOptions options_;
  EvalIbrOptions eval_;
  IbrOptions ibr_;
  QualityOptions quality_;
  CLI::App* command_ = nullptr;
  CLI::Option* frames_ = nullptr;
};

}  // namespace

std::unique_ptr<Command> make_eval_ibr_command() { return std::make_unique<EvalIbrCommand>(); }

}  // namespace rt::app
