#pragma once
// A synthetic calibration site's chessboard views as its cameras would record them: each board
// pose rendered through each camera's lens (distortion included) and written as k4a recordings,
// one a second as a person would hold the board still. `calibrate synthesize --board-recording`
// writes it, so that `calibrate extrinsics --views-from` can be tried, and checked against the
// truth, without the hardware.
#include <filesystem>

#include "calibration/synthetic_site.h"

namespace rt::camera {

// Writes `dir`/site.json and one `<camera name>.mkv` per camera of `site.truth` (colour 1280x720
// MJPG at `jpeg_quality`, an empty NFOV 2x2-binned depth image beside each). Throws
// std::invalid_argument when a camera's colour size is not a k4a resolution.
void write_board_recording(const calibration::SyntheticSite& site, const std::filesystem::path& dir, int jpeg_quality);

}  // namespace rt::camera
