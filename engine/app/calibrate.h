#pragma once
// `remotetouch calibrate intrinsics | extrinsics | tracker | synthesize`: the site calibration
// (paper section 4, "Device Calibration"), one file per command. Runs on the CPU.
#include <CLI/CLI.hpp>

#include "app/command.h"

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace rt::app {

struct IntrinsicsCommandOptions {
  std::vector<std::string> images;
  std::string board;
  double square_m = 0;
  std::filesystem::path out;
  bool fix_aspect_ratio = false;
  bool rational_model = false;
};

// `calibrate extrinsics` and `calibrate tracker` update a site file (sim/site_description.h) in place.
struct ExtrinsicsCommandOptions {
  std::filesystem::path input;
  std::filesystem::path site;
  double max_distance_residual_mm = 0;
  double max_link_rms_px = 0;
  double max_alignment_residual_mm = 0;
  std::filesystem::path views_from;  // a recording of the site's cameras; empty: the input's views
  double view_every_s = 0;
};

struct TrackerCommandOptions {
  std::filesystem::path input;
  std::filesystem::path site;
  double inlier_threshold_mm = 0;
};

struct SynthesizeCommandOptions {
  std::filesystem::path out;
  double corner_noise_px = 0;
  double distance_noise_mm = 0;
  double tip_noise_mm = 0;
  size_t tip_outliers = 0;
  uint32_t seed = 0;
  bool board_recording = false;
  int jpeg_quality = 0;
};

int run_calibrate_intrinsics(const IntrinsicsCommandOptions& options);
int run_calibrate_extrinsics(const ExtrinsicsCommandOptions& options);
int run_calibrate_tracker(const TrackerCommandOptions& options);
int run_calibrate_synthesize(const SynthesizeCommandOptions& options);

// --device on a calibration command: accepted, so that a script can pass it to every command,
// and not used (calibration runs on the CPU).
inline void add_unused_device_option(CLI::App& command, std::string& device) {
  command.add_option("--device", device, "Not used: calibration runs on the CPU (accepted like on the GPU commands)");
}

}  // namespace rt::app
