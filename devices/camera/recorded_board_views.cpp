#include "camera/recorded_board_views.h"

#include <opencv2/core.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <optional>

#include "calibration/calibration_error.h"
#include "calibration/chessboard.h"

namespace rt::camera {
namespace {

using calibration::CalibrationError;

// The corner finder works on grey; an image holds its channels as floats in [0, 1].
cv::Mat gray_of(const HostImage& color) {
  cv::Mat gray(int(color.height), int(color.width), CV_8UC1);
  for (uint32_t y = 0; y < color.height; ++y)
    for (uint32_t x = 0; x < color.width; ++x) {
      const float luma = 0.299f * color.at(x, y, 0) + 0.587f * color.at(x, y, 1) + 0.114f * color.at(x, y, 2);
      gray.at<uint8_t>(int(y), int(x)) = uint8_t(std::lround(std::isfinite(luma) ? std::clamp(luma, 0.0f, 1.0f) * 255.0f : 0.0f));
    }
  return gray;
}

// Index of the recording's camera of each of the input's cameras.
std::vector<size_t> recorded_camera_of_each(const calibration::ExtrinsicsInput& input,
                                            const sim::RecordedRgbdSource& recording, const std::string& where) {
  const auto& cameras = recording.site().cameras;
  std::vector<size_t> recorded;
  for (const calibration::CameraSetup& setup : input.cameras) {
    size_t k = 0;
    while (k < cameras.size() && cameras[k].name != setup.name) ++k;
    if (k == cameras.size()) {
      std::string names;
      for (const auto& camera : cameras) names += (names.empty() ? "'" : ", '") + camera.name + "'";
      throw CalibrationError(where + ": camera '" + setup.name + "' of the input is not in the recording, which has " +
                             names);
    }
    recorded.push_back(k);
  }
  return recorded;
}

}  // namespace

RecordedBoardViews add_recorded_board_views(calibration::ExtrinsicsInput& input, sim::RecordedRgbdSource& recording,
                                            double every_s, const std::string& where) {
  if (!std::isfinite(every_s) || every_s < 0)
    throw CalibrationError(where + ": the time between views must be zero or more seconds, not " +
                           std::to_string(every_s));
  const std::vector<size_t> recorded = recorded_camera_of_each(input, recording, where);
  for (size_t c = 0; c < input.cameras.size(); ++c) {
    calibration::CameraSetup& setup = input.cameras[c];
    const CameraIntrinsics& factory = recording.recorded_intrinsics().at(recorded[c]).color;
    if (!setup.intrinsics_given) {
      setup.intrinsics = factory;
      setup.intrinsics_given = true;
    } else if (setup.intrinsics.width != factory.width || setup.intrinsics.height != factory.height) {
      throw CalibrationError(where + ": camera '" + setup.name + "' has intrinsics for " +
                             std::to_string(setup.intrinsics.width) + "x" + std::to_string(setup.intrinsics.height) +
                             ", its recording's colour images are " + std::to_string(factory.width) + "x" +
                             std::to_string(factory.height));
    }
  }

  RecordedBoardViews result;
  result.board_missed.assign(input.cameras.size(), 0);
  const uint64_t every_us = uint64_t(std::llround(every_s * 1e6));
  std::optional<uint64_t> last_taken_us;
  for (size_t i = 0; i < recording.frame_count(); ++i) {
    const uint64_t time_us = recording.frame_timestamp_us(i);
    if (last_taken_us && time_us < *last_taken_us + every_us) continue;
    last_taken_us = time_us;
    recording.seek(i);
    const std::optional<sim::RgbdFrame> frame = recording.next_frame();
    if (!frame) break;
    ++result.frame_sets_searched;
    calibration::BoardSnapshot snapshot;
    char name[64];
    std::snprintf(name, sizeof name, "set %zu (%.2f s)", i, double(time_us - recording.frame_timestamp_us(0)) * 1e-6);
    snapshot.name = name;
    for (size_t c = 0; c < input.cameras.size(); ++c) {
      const sim::RgbdImage* image = nullptr;
      for (const sim::RgbdImage& candidate : frame->cameras)
        if (candidate.camera == input.cameras[c].name) image = &candidate;
      // A camera that dropped this capture has an empty image: it did not see the board.
      std::optional<std::vector<cv::Point2f>> corners;
      if (image && image->color.width == input.cameras[c].intrinsics.width &&
          image->color.height == input.cameras[c].intrinsics.height)
        corners = calibration::find_chessboard(gray_of(image->color), input.board);
      if (corners)
        snapshot.observations.push_back({input.cameras[c].name, std::move(*corners)});
      else
        ++result.board_missed[c];
    }
    if (snapshot.observations.empty()) continue;
    input.snapshots.push_back(std::move(snapshot));
    ++result.views_added;
  }
  for (size_t c = 0; c < input.cameras.size(); ++c)
    if (result.board_missed[c] > 0)
      input.board_not_found.push_back("camera '" + input.cameras[c].name + "': in " +
                                      std::to_string(result.board_missed[c]) + " of " +
                                      std::to_string(result.frame_sets_searched) + " frame sets of the recording");
  return result;
}

}  // namespace rt::camera
