// `remotetouch calibrate synthesize`: a simulated site's calibration inputs with their truth,
// so that the calibration can be tried, and checked, without the hardware.
#include <cstdio>

#include "app/calibrate.h"
#include "calibration/synthetic_site.h"
#include "camera/synthetic_board_recording.h"
#include "config/json.h"

namespace rt::app {

int run_calibrate_synthesize(const SynthesizeCommandOptions& options) {
  calibration::SyntheticSiteOptions site_options;
  site_options.corner_noise_px = options.corner_noise_px;
  site_options.distance_noise_mm = options.distance_noise_mm;
  site_options.tip_noise_mm = options.tip_noise_mm;
  site_options.tip_outliers = options.tip_outliers;
  site_options.seed = options.seed;
  const calibration::SyntheticSite site = calibration::make_synthetic_site(site_options);
  calibration::write_synthetic_site(site, options.out);
  std::printf("wrote a simulated site to %s: %zu cameras, %zu chessboard views, %zu touches (%zu slipped)\n",
              options.out.c_str(), site.extrinsics_input.cameras.size(), site.extrinsics_input.snapshots.size(),
              site.touches.size(), options.tip_outliers);
  std::printf("calibrate it into a copy of the default site:\n  cp assets/sites/default.json SITE.json\n");
  std::printf("  remotetouch calibrate extrinsics --input %s --site SITE.json\n",
              (options.out / "extrinsics_input.json").c_str());
  std::printf("  remotetouch calibrate tracker --input %s --site SITE.json\n",
              (options.out / "tracker_touches.json").c_str());
  if (options.board_recording) {
    // The same views as the cameras record them, and an input that takes them from there.
    const std::filesystem::path recording = options.out / "board_recording";
    camera::write_board_recording(site, recording, options.jpeg_quality);
    nlohmann::json input = config::read_json_file(options.out / "extrinsics_input.json");
    input.erase("views");
    for (nlohmann::json& camera : input["cameras"]) camera.erase("intrinsics");
    config::write_json_file(options.out / "extrinsics_from_recording.json", input);
    std::printf("wrote the board views as k4a recordings of the cameras to %s; calibrate from them:\n",
                recording.c_str());
    std::printf("  remotetouch calibrate extrinsics --input %s --views-from %s --site SITE.json\n",
                (options.out / "extrinsics_from_recording.json").c_str(), recording.c_str());
  }
  std::printf("the truth: %s, %s\n", (options.out / "truth_site.json").c_str(),
              (options.out / "truth_touch_outliers.json").c_str());
  return 0;
}

namespace {

class CalibrateSynthesizeCommand : public Command {
 public:
  CLI::App* add_to(CLI::App& parent) override {
    SynthesizeCommandOptions& sy = options_;
    const calibration::SyntheticSiteOptions defaults;
    sy.out = "out/calibration/synthetic";
    sy.corner_noise_px = defaults.corner_noise_px;
    sy.distance_noise_mm = defaults.distance_noise_mm;
    sy.tip_noise_mm = defaults.tip_noise_mm;
    sy.tip_outliers = defaults.tip_outliers;
    sy.seed = defaults.seed;
    CLI::App* command = parent.add_subcommand(
        "synthesize", "Write the inputs of `calibrate extrinsics` and `calibrate tracker` for a simulated site, "
                      "with its true calibration, to try and check the calibration");
    command->add_option("--out", sy.out, "Folder to write")->capture_default_str();
    add_unused_device_option(*command, unused_device_);
    command->add_option("--corner-noise-px", sy.corner_noise_px, "Noise on the chessboard corners (sigma)")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str();
    command->add_option("--distance-noise-mm", sy.distance_noise_mm, "Noise on the measured distances (sigma)")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str();
    command->add_option("--tip-noise-mm", sy.tip_noise_mm, "Noise on the fingertip positions (sigma, per axis)")
        ->check(CLI::NonNegativeNumber)
        ->capture_default_str();
    command->add_option("--tip-outliers", sy.tip_outliers, "Touches that slipped by 30 to 60 mm")
        ->check(CLI::Range(0, 20))
        ->capture_default_str();
    command->add_option("--seed", sy.seed, "Random seed")->capture_default_str();
    command->add_flag("--board-recording", sy.board_recording,
                      "Also write the chessboard views as k4a recordings of the cameras (board_recording/) and an "
                      "input that takes its views and intrinsics from them (extrinsics_from_recording.json)");
    sy.jpeg_quality = 90;
    command->add_option("--jpeg-quality", sy.jpeg_quality, "With --board-recording: the colour's MJPG quality")
        ->check(CLI::Range(1, 100))
        ->capture_default_str();
    return command;
  }
  int run() override { return run_calibrate_synthesize(options_); }

 private:
  SynthesizeCommandOptions options_;
  std::string unused_device_;
};

}  // namespace

std::unique_ptr<Command> make_calibrate_synthesize_command() { return std::make_unique<CalibrateSynthesizeCommand>(); }

}  // namespace rt::app
