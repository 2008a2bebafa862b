#pragma once
// What `remotetouch inspect-camera` writes for a k4a recording: the recorded configuration,
// the intrinsics at the recorded modes in our camera model, colour-from-depth, and the first
// captures as images (colour PNG, depth as 16-bit millimetres exactly as recorded) and as
// coloured points. What needs a GPU (depth registered into colour) is the caller's, through a
// hook: devices own no Vulkan objects.
#include <nlohmann/json.hpp>

#include <array>
#include <filesystem>
#include <functional>
#include <span>

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

// Called for each capture after its own files are written, with the recording's info.
using CaptureHook = std::function<void(size_t index, const Capture& capture, const RecordingInfo& info)>;

// Reads up to `max_captures` captures into `out`: camera.json (the above plus "captures", one
// {index, color_device_us, depth_device_us, points} each, null for a missing image),
// color_NNNN.png, depth_NNNN.png and points_NNNN.ply (write_points_ply) for a capture with depth.
// Throws RecordingError for a bad file, and for one with no captures at all.
InspectionSummary inspect_recording(const std::filesystem::path& recording, size_t max_captures,
                                    const std::filesystem::path& out, const CaptureHook& on_capture = {});

// Binary little-endian PLY, one vertex per measured depth pixel in row order: x, y, z (float,
// metres, the depth camera's frame: ray * depth, rays from geometry/pixel_rays.h)
// and red, green, blue (uchar) of the colour pixel nearest to where the point projects, 0 0 0
// where it falls outside the colour image, behind it, or there is no colour. The header is
// exactly:
//   ply / format binary_little_endian 1.0 / element vertex N / property float x / property
//   float y / property float z / property uchar red / property uchar green / property uchar
//   blue / end_header
// one line each. Returns N.
size_t write_points_ply(const std::filesystem::path& path, const HostImage& depth_mm, const HostImage& color,
                        std::span<const std::array<float, 2>> depth_rays, const RecordingInfo& info);

}  // namespace rt::camera::k4a
