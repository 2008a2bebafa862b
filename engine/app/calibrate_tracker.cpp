// `remotetouch calibrate tracker`: the hand tracker's pose in the site frame, written into the
// site file.
#include <cmath>
#include <cstdio>

#include "app/calibrate.h"
#include "calibration/site_update.h"
#include "calibration/tracker_calibration.h"

namespace rt::app {

int run_calibrate_tracker(const TrackerCommandOptions& options) {
  const auto touches = calibration::read_tracker_touches(options.input);
  sim::SiteDescription site = calibration::load_site_to_update(options.site);
  const calibration::TrackerCalibration result = calibration::calibrate_tracker(touches, options.inlier_threshold_mm);

  std::printf("%zu touches; a touch farther than %.1f mm from its screen point is rejected\n", touches.size(),
              options.inlier_threshold_mm);
  std::printf("%-16s %12s\n", "touch", "residual");
  for (size_t i = 0; i < touches.size(); ++i)
    std::printf("%-16s %9.2f mm%s\n", touches[i].label.c_str(), result.residuals_mm[i],
                result.inlier[i] ? "" : "  rejected");
  const size_t rejected = touches.size() - result.inlier_count();
  std::printf("rejected %zu of %zu touches\n", rejected, touches.size());
  std::printf("residual RMS %.2f mm over the %zu touches kept\n", result.inlier_rms_mm, result.inlier_count());
  const Eigen::Vector3d origin = result.site_from_tracker.translation();
  const Eigen::AngleAxisd turn(result.site_from_tracker.linear());
  std::printf("tracker origin in site (m): (%+.4f, %+.4f, %+.4f); turned %.2f degrees about (%+.3f, %+.3f, %+.3f)\n",
              origin.x(), origin.y(), origin.z(), turn.angle() * 180.0 / 3.14159265358979323846, turn.axis().x(),
              turn.axis().y(), turn.axis().z());

  calibration::apply_tracker_calibration(site, result);
  calibration::write_updated_site(options.site, site);
  std::printf("updated %s (tracker pose; kept the cameras, seat, touch region, motor)\n", options.site.c_str());
  return 0;
}

namespace {

class CalibrateTrackerCommand : public Command {
 public:
  CLI::App* add_to(CLI::App& parent) override {
    TrackerCommandOptions& tr = options_;
    tr.inlier_threshold_mm = calibration::kDefaultInlierThresholdMm;
    CLI::App* command = parent.add_subcommand(
        "tracker", "The hand tracker's pose in the site frame from fingertip touches on known screen points");
    command->add_option("--input", tr.input, "Touches JSON (see engine/calibration/tracker_calibration.h)")
        ->required()
        ->check(CLI::ExistingFile);
    command->add_option("--site", tr.site,
                         "Site file to update in place (start from a copy of assets/sites/default.json): "
                         "the tracker pose and its residual; the rest is kept")
        ->required();
    add_unused_device_option(*command, unused_device_);
    command->add_option("--inlier-threshold-mm", tr.inlier_threshold_mm,
                         "A touch farther than this from its screen point is rejected")
        ->check(CLI::PositiveNumber)
        ->capture_default_str();
    return command;
  }
  int run() override { return run_calibrate_tracker(options_); }

 private:
  TrackerCommandOptions options_;
  std::string unused_device_;
};

}  // namespace

std::unique_ptr<Command> make_calibrate_tracker_command() { return std::make_unique<CalibrateTrackerCommand>(); }

}  // namespace rt::app
