#pragma once
// What `remotetouch inspect-camera` writes for a k4a recording: the recorded configuration,
// the intrinsics at the recorded modes in our camera model, colour-from-depth, and the first
// captures as images (colour PNG, depth as 16-bit millimetres exactly as recorded).
#include <nlohmann/json.hpp>

#include <filesystem>

#include "camera/k4a_recording_reader.h"

namespace rt::camera::k4a {

// {"config": {color_format, color_resolution [w, h], depth_mode, fps, wired_sync_mode,
//  depth_delay_ns, subordinate_delay_ns, start_offset_us, serial}, "color": intrinsics,
//  "depth": intrinsics, "color_from_depth": 4x4 row-major, metres}. Intrinsics in OpenCV's
// convention: width, height, fx, fy, cx, cy, k1..k6, p1, p2.
nlohmann::json recording_info_to_json(const RecordingInfo& info);

struct InspectionSummary {
  size_t captures = 0;
  double decode_ms = 0;  // demuxing and decoding them all, PNG writing left out
};

// Reads up to `max_captures` captures into `out`: camera.json (the above plus "captures", one
// {index, color_device_us, depth_device_us} each, null for a missing image), color_NNNN.png and
// depth_NNNN.png. Throws RecordingError for a bad file, and for one with no captures at all.
InspectionSummary inspect_recording(const std::filesystem::path& recording, size_t max_captures,
                                    const std::filesystem::path& out);

}  // namespace rt::camera::k4a
