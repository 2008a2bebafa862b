#include "camera/k4a_inspection.h"

#include <opencv2/calib3d.hpp>

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <vector>

#include "config/json.h"
#include "geometry/pixel_rays.h"
#include "image/image_io.h"

namespace rt::camera::k4a {

namespace {

nlohmann::json intrinsics_json(const CameraIntrinsics& k) {
  const Distortion& d = k.distortion;
  return {{"width", k.width}, {"height", k.height}, {"fx", k.fx}, {"fy", k.fy}, {"cx", k.cx},
          {"cy", k.cy},       {"k1", d.k1},         {"k2", d.k2}, {"k3", d.k3}, {"k4", d.k4},
          {"k5", d.k5},       {"k6", d.k6},         {"p1", d.p1}, {"p2", d.p2}};
}

std::string numbered(const char* stem, size_t index, const char* extension = "png") {
  char name[64];
  std::snprintf(name, sizeof(name), "%s_%04zu.%s", stem, index, extension);
  return name;
}

uint8_t byte_of(float unit) { return uint8_t(std::lround(std::clamp(unit, 0.0f, 1.0f) * 255.0f)); }

}  // namespace

nlohmann::json recording_info_to_json(const RecordingInfo& info) {
  const SensorCut& cut = sensor_cut(info.color_resolution);
  nlohmann::json transform = nlohmann::json::array();
  const Eigen::Matrix4d m = info.color_from_depth().matrix();
  for (int row = 0; row < 4; ++row) transform.push_back({m(row, 0), m(row, 1), m(row, 2), m(row, 3)});
  return {{"config",
           {{"color_format", color_format_name(info.color_format)},
            {"color_resolution", {cut.output_width, cut.output_height}},
            {"depth_mode", depth_mode_name(info.depth_mode)},
            {"fps", info.fps},
            {"wired_sync_mode", wired_sync_mode_name(info.wired_sync)},
            {"depth_delay_ns", info.depth_delay_ns},
            {"subordinate_delay_ns", info.subordinate_delay_ns},
            {"start_offset_us", info.start_offset_us},
            {"serial", info.serial}}},
          {"color", intrinsics_json(info.color)},
          {"depth", intrinsics_json(info.depth)},
          {"color_from_depth", transform}};
}

size_t write_points_ply(const std::filesystem::path& path, const HostImage& depth_mm, const HostImage& color,
                        std::span<const std::array<float, 2>> depth_rays, const RecordingInfo& info) {
  static_assert(std::endian::native == std::endian::little, "the PLY is written in the machine's byte order");
  if (depth_rays.size() != size_t(depth_mm.width) * depth_mm.height)
    throw std::invalid_argument("points: " + std::to_string(depth_rays.size()) + " rays for a " +
                                std::to_string(depth_mm.width) + "x" + std::to_string(depth_mm.height) + " depth image");
  std::vector<cv::Point3d> points;
  std::vector<bool> in_front;
  const Eigen::Isometry3d color_from_depth = info.color_from_depth();
  for (size_t i = 0; i < depth_rays.size(); ++i) {
    const float mm = depth_mm.texels[i];
    if (mm == 0.0f) continue;
    const double z = mm * 0.001;
    // A pixel without a ray still counts as a point, at its depth on the axis, so that the
    // points are the measured pixels, one for one.
    const auto& ray = depth_rays[i];
    const bool has_ray = std::isfinite(ray[0]) && std::isfinite(ray[1]);
    points.emplace_back(has_ray ? ray[0] * z : 0.0, has_ray ? ray[1] * z : 0.0, z);
    in_front.push_back((color_from_depth * Eigen::Vector3d(points.back().x, points.back().y, z)).z() > 1e-3);
  }
  std::vector<cv::Point2d> pixels;
  if (!points.empty()) {
    const Eigen::Matrix3d r = color_from_depth.rotation();
    cv::Vec3d rvec;
    cv::Rodrigues(cv::Matx33d(r(0, 0), r(0, 1), r(0, 2), r(1, 0), r(1, 1), r(1, 2), r(2, 0), r(2, 1), r(2, 2)), rvec);
    const Eigen::Vector3d t = color_from_depth.translation();
    const CameraIntrinsics& k = info.color;
    const auto coefficients = k.distortion.as_opencv();
    cv::projectPoints(points, rvec, cv::Vec3d(t.x(), t.y(), t.z()), cv::Matx33d(k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1),
                      cv::Mat(int(coefficients.size()), 1, CV_64F, const_cast<double*>(coefficients.data())), pixels);
  }
  std::ofstream file(path, std::ios::binary);
  file << "ply\nformat binary_little_endian 1.0\nelement vertex " << points.size()
       << "\nproperty float x\nproperty float y\nproperty float z\nproperty uchar red\nproperty uchar green\n"
          "property uchar blue\nend_header\n";
  std::vector<char> body(points.size() * 15);
  for (size_t i = 0; i < points.size(); ++i) {
    const float xyz[3] = {float(points[i].x), float(points[i].y), float(points[i].z)};
    uint8_t rgb[3] = {0, 0, 0};
    const double u = std::floor(pixels[i].x + 0.5), v = std::floor(pixels[i].y + 0.5);
    if (in_front[i] && color.width > 0 && u >= 0 && v >= 0 && u < color.width && v < color.height)
      for (uint32_t c = 0; c < 3; ++c) rgb[c] = byte_of(color.at(uint32_t(u), uint32_t(v), c));
    std::memcpy(&body[i * 15], xyz, 12);
    std::memcpy(&body[i * 15 + 12], rgb, 3);
  }
  file.write(body.data(), std::streamsize(body.size()));
  if (!file) throw std::runtime_error("cannot write '" + path.string() + "'");
  return points.size();
}

InspectionSummary inspect_recording(const std::filesystem::path& recording, size_t max_captures,
                                    const std::filesystem::path& out, const CaptureHook& on_capture) {
  RecordingReader reader(recording);
  const std::vector<std::array<float, 2>> depth_rays = undistorted_pixel_rays(reader.info().depth);
  std::filesystem::create_directories(out);
  nlohmann::json document = recording_info_to_json(reader.info());
  nlohmann::json captures = nlohmann::json::array();
  InspectionSummary summary;
  while (summary.captures < max_captures) {
    const auto start = std::chrono::steady_clock::now();
    const std::optional<Capture> capture = reader.next_capture();
    summary.decode_ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    if (!capture) break;
    const size_t index = summary.captures++;
    nlohmann::json entry = {
        {"index", index}, {"color_device_us", nullptr}, {"depth_device_us", nullptr}, {"points", nullptr}};
    if (capture->color_device_us) {
      entry["color_device_us"] = *capture->color_device_us;
      write_image(out / numbered("color", index), capture->color);
    }
    if (capture->depth_device_us) {
      entry["depth_device_us"] = *capture->depth_device_us;
      write_image(out / numbered("depth", index), capture->depth_mm, PngDepth::Sixteen);
      entry["points"] = write_points_ply(out / numbered("points", index, "ply"), capture->depth_mm, capture->color,
                                         depth_rays, reader.info());
    }
    captures.push_back(entry);
    if (on_capture) on_capture(index, *capture, reader.info());
  }
  if (summary.captures == 0)
    throw RecordingError("'" + recording.string() + "': no captures (the recording holds no COLOR or DEPTH frame)");
  document["captures"] = captures;
  config::write_json_file(out / "camera.json", document);
  return summary;
}

}  // namespace rt::camera::k4a
