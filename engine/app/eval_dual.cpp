// The command line of eval dual; the work itself is pipeline/jobs/eval_dual.cpp.
#include "app/command.h"
#include "app/option_groups.h"
#include "pipeline/jobs.h"

namespace rt::app {

using namespace rt::pipeline;

namespace {

class EvalDualCommand : public Command {
 public:
  CLI::App* add_to(CLI::App& parent) override {
    CLI::App* command = command_ = parent.add_subcommand(
        "dual", "The receiver's whole chain (portrait, geometry hand, fusion) on the hand and forearm, per touch phase: "
                "metrics.json, frames.csv, hand_psnr.png, contact sheets");
    command->add_option("--scene", eval_.scene, "Scene name under assets/scenes/, or a scene file")->capture_default_str();
    command->add_option("--users", eval_.users, "Whose hand is measured (as the other site sees it)")
        ->delimiter(',')
        ->check(CLI::IsMember({"A", "B"}))
        ->capture_default_str();
    command
        ->add_option("--variants", eval_.variants,
                     "image, geometry, dual, dual_no_appearance, dual_no_shape, hard_switch, dual_predicted (comma-separated; "
                     "default all, dual_predicted only with --tracker-latency)")
        ->delimiter(',')
        ->check(CLI::IsMember(
            {"image", "geometry", "dual", "dual_no_appearance", "dual_no_shape", "hard_switch", "dual_predicted"}));
    command->add_option("--first-frame", eval_.first_frame, "Scene frame to start at")
        ->check(CLI::Range(0u, 1000000u))
        ->capture_default_str();
    command->add_option("--frame-step", eval_.frame_step, "Every Nth scene frame (adaption then sees only those)")
        ->check(CLI::Range(1u, 1000u))
        ->capture_default_str();
    command->add_option("--resolution-scale", eval_.resolution_scale, "Camera resolution scale (1 is the site's own)")
        ->check(CLI::Range(0.01, 1.0))
        ->default_str("the scene's");
    command
        ->add_option("--tracker-latency", eval_.tracker_latency_ms,
                     "The remote skeletons arrive this many ms after their capture: the hand is posed from the newest "
                     "one then, and the variant dual_predicted carries it forward to the display time")
        ->check(CLI::Range(0.0, 1000.0))
        ->capture_default_str();
    command->add_flag("--no-plots", no_plots_, "Skip hand_psnr.png and the contact sheets (they need python3-matplotlib)");
    ibr_ = add_ibr_options(*command);
    quality_.add_to(*command);
    hand_ = add_hand_options(*command);
    add_run_options(*command, options_, "out/eval-dual");
    frames_ = add_frames_option(*command, options_, 1, "the rest of the scene from --first-frame at --frame-step");
    options_.width = 640;
    options_.height = 360;
    add_size_options(*command, options_, "Target view", 16, 16384);
    return command;
  }
  void check() override {
    eval_.frames_given = frames_->count() > 0;
    eval_.plots = !no_plots_;
    eval_.ibr.width = options_.width;
    eval_.ibr.height = options_.height;
    eval_.quality = quality_.apply(eval_.ibr, eval_.resolution_scale, command_->count("--resolution-scale") > 0);
    ibr_.apply(eval_.ibr);
    hand_.apply(eval_.hand);
  }
  int run() override { return run_eval_dual(options_, eval_); }

 private:
  RunOptions options_;
  EvalDualOptions eval_;
  IbrOptions ibr_;
  QualityOptions quality_;
  CLI::App* command_ = nullptr;
  HandOptions hand_;
  CLI::Option* frames_ = nullptr;
  bool no_plots_ = false;
};

}  // namespace

std::unique_ptr<Command> make_eval_dual_command() { return std::make_unique<EvalDualCommand>(); }

}  // namespace rt::app
