#include "camera/k4a_inspection.h"

#include <chrono>
#include <cstdio>

#include "config/json.h"
#include "image/image_io.h"

namespace rt::camera::k4a {

namespace {

nlohmann::json intrinsics_json(const CameraIntrinsics& k) {
  const Distortion& d = k.distortion;
  return {{"width", k.width}, {"height", k.height}, {"fx", k.fx}, {"fy", k.fy}, {"cx", k.cx},
          {"cy", k.cy},       {"k1", d.k1},         {"k2", d.k2}, {"k3", d.k3}, {"k4", d.k4},
          {"k5", d.k5},       {"k6", d.k6},         {"p1", d.p1}, {"p2", d.p2}};
}

std::string numbered(const char* stem, size_t index) {
  char name[64];
  std::snprintf(name, sizeof(name), "%s_%04zu.png", stem, index);
  return name;
}

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

InspectionSummary inspect_recording(const std::filesystem::path& recording, size_t max_captures,
                                    const std::filesystem::path& out) {
  RecordingReader reader(recording);
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
    nlohmann::json entry = {{"index", index}, {"color_device_us", nullptr}, {"depth_device_us", nullptr}};
    if (capture->color_device_us) {
      entry["color_device_us"] = *capture->color_device_us;
      write_image(out / numbered("color", index), capture->color);
    }
    if (capture->depth_device_us) {
      entry["depth_device_us"] = *capture->depth_device_us;
      write_image(out / numbered("depth", index), capture->depth_mm, PngDepth::Sixteen);
    }
    captures.push_back(entry);
  }
  if (summary.captures == 0)
    throw RecordingError("'" + recording.string() + "': no captures (the recording holds no COLOR or DEPTH frame)");
  document["captures"] = captures;
  config::write_json_file(out / "camera.json", document);
  return summary;
}

}  // namespace rt::camera::k4a
