// `remotetouch calibrate intrinsics`: Zhang's method on a set of photographs, with a report that
// names the photographs where the board was not found and those that fit badly.
#include <algorithm>
#include <cstdio>

#include "app/calibrate.h"
#include "calibration/image_files.h"
#include "calibration/intrinsics_calibration.h"
#include "config/json.h"

namespace rt::app {
namespace {

// A photograph whose error is this many times the median is worth a look (motion blur, a
// mis-detected corner); it is reported, not dropped, so the user decides.
constexpr double kSuspectErrorFactor = 3.0;

double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  return values.empty() ? 0.0 : values[values.size() / 2];
}

void print_report(const calibration::ImageSetCalibration& calibration, const calibration::Chessboard& board,
                  size_t image_count) {
  const auto& result = calibration.result;
  std::printf("board (%s) found in %zu of %zu images\n", board.describe().c_str(), calibration.used_images.size(),
              image_count);
  if (!calibration.board_not_found.empty()) {
    std::printf("board not found in:\n");
    for (const auto& path : calibration.board_not_found) std::printf("  %s\n", path.c_str());
  }
  const double typical = median(result.view_rms_error_px);
  std::printf("per-image RMS reprojection error:\n");
  for (size_t i = 0; i < calibration.used_images.size(); ++i) {
    const double error = result.view_rms_error_px[i];
    std::printf("  %-40s %.3f px%s\n", calibration.used_images[i].filename().c_str(), error,
                error > kSuspectErrorFactor * typical ? "  (high: check this photograph)" : "");
  }
  const CameraIntrinsics& k = result.intrinsics;
  const Distortion& d = k.distortion;
  std::printf("image %ux%u\n", k.width, k.height);
  const calibration::IntrinsicsStdDev& sd = result.std_dev_px;
  std::printf("fx %.3f +- %.3f  fy %.3f +- %.3f  cx %.3f +- %.3f  cy %.3f +- %.3f  (px, +- one standard deviation)\n",
              k.fx, sd.fx, k.fy, sd.fy, k.cx, sd.cx, k.cy, sd.cy);
  std::printf("distortion k1 %.6f  k2 %.6f  p1 %.6f  p2 %.6f  k3 %.6f", d.k1, d.k2, d.p1, d.p2, d.k3);
  if (d.k4 != 0 || d.k5 != 0 || d.k6 != 0) std::printf("  k4 %.6f  k5 %.6f  k6 %.6f", d.k4, d.k5, d.k6);
  std::printf("\nRMS reprojection error %.4f px over %zu images\n", result.rms_error_px, calibration.used_images.size());
}

}  // namespace

int run_calibrate_intrinsics(const IntrinsicsCommandOptions& options) {
  const calibration::Chessboard board = calibration::parse_chessboard(options.board, options.square_m);
  const auto images = calibration::expand_image_patterns(options.images);
  const calibration::IntrinsicsOptions model{options.fix_aspect_ratio, options.rational_model};
  const auto calibration = calibration::calibrate_intrinsics_from_images(images, board, model);
  print_report(calibration, board, images.size());
  config::write_json_file(options.out, calibration::intrinsics_report_json(calibration, board, model));
  std::printf("wrote %s\n", options.out.c_str());
  return 0;
}

namespace {

class CalibrateIntrinsicsCommand : public Command {
 public:
  CLI::App* add_to(CLI::App& parent) override {
    IntrinsicsCommandOptions& in = options_;
    in.out = "out/calibration/intrinsics.json";
    CLI::App* command = parent.add_subcommand(
        "intrinsics", "One camera's focal lengths, principal point and distortion from chessboard photographs (Zhang)");
    command->add_option("--images", in.images, "Photographs: paths or quoted patterns such as 'data/left*.jpg'")
        ->required();
    command->add_option("--board", in.board, "Inner corners per row and per column, COLSxROWS (e.g. 9x6)")->required();
    command->add_option("--square", in.square_m, "Side of one square in metres (e.g. 0.025)")->required();
    command->add_option("--out", in.out, "Camera JSON to write")->capture_default_str();
    add_unused_device_option(*command, unused_device_);
    command->add_flag("--fix-aspect-ratio", in.fix_aspect_ratio, "Square pixels: estimate one focal length (fx = fy)");
    command->add_flag("--rational-model", in.rational_model, "Also estimate k4, k5, k6 (wide-angle lenses)");
    return command;
  }
  int run() override { return run_calibrate_intrinsics(options_); }

 private:
  IntrinsicsCommandOptions options_;
  std::string unused_device_;
};

}  // namespace

std::unique_ptr<Command> make_calibrate_intrinsics_command() { return std::make_unique<CalibrateIntrinsicsCommand>(); }

}  // namespace rt::app
