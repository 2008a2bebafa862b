#include "sim/recording.h"

#include <cstdio>
#include <stdexcept>

#include "config/json.h"
#include "image/image_io.h"
#include "image/png_header.h"

namespace rt::sim {
namespace {

std::string numbered(const char* stem, uint64_t frame, const char* extension) {
  char name[64];
  std::snprintf(name, sizeof name, "%s_%06llu.%s", stem, static_cast<unsigned long long>(frame), extension);
  return name;
}

std::vector<std::string> camera_names_of(const nlohmann::json& calibration, const std::string& where) {
  std::vector<std::string> names;
  for (const auto& camera : config::require_array(calibration, "cameras", where, 1))
    names.push_back(config::require_string(camera, "name", where + " camera"));
  return names;
}

// 8-bit mask: 255 where the test holds.
HostImage mask_where(const HostImage& part, bool (*keep)(float)) {
  HostImage mask(part.width, part.height, PixelFormat::R32F);
  for (size_t i = 0; i < part.texels.size(); ++i) mask.texels[i] = keep(part.texels[i]) ? 1.0f : 0.0f;
  return mask;
}

}  // namespace

std::filesystem::path color_path(const std::filesystem::path& dir, size_t camera, uint64_t frame) {
  return dir / ("cam" + std::to_string(camera)) / numbered("color", frame, "png");
}

std::filesystem::path depth_path(const std::filesystem::path& dir, size_t camera, uint64_t frame) {
  return dir / ("cam" + std::to_string(camera)) / numbered("depth", frame, "png");
}

std::filesystem::path ground_truth_color_path(const std::filesystem::path& dir, uint64_t frame) {
  return dir / "gt" / numbered("target_color", frame, "png");
}

RecordingWriter::RecordingWriter(const std::filesystem::path& dir, nlohmann::json calibration) : dir_(dir) {
  camera_names_ = camera_names_of(calibration, "recording calibration");
  calibration["format"] = kRecordingFormat;
  std::filesystem::create_directories(dir_);
  config::write_json_file(dir_ / "calibration.json", calibration);
  frames_.open(dir_ / "frames.jsonl");
  if (!frames_) throw std::runtime_error("cannot write '" + (dir_ / "frames.jsonl").string() + "'");
}

void RecordingWriter::write_frame(const RgbdFrame& frame) {
  if (frame.cameras.size() != camera_names_.size())
    throw std::invalid_argument("recording frame " + std::to_string(frame.index) + " has " +
                                std::to_string(frame.cameras.size()) + " cameras, the calibration " +
                                std::to_string(camera_names_.size()));
  nlohmann::json line = {{"frame", frame.index}, {"timestamp_us", frame.timestamp_us}, {"cameras", nlohmann::json::array()}};
  for (size_t k = 0; k < frame.cameras.size(); ++k) {
    const RgbdImage& image = frame.cameras[k];
    if (image.camera != camera_names_[k])
      throw std::invalid_argument("recording: camera " + std::to_string(k) + " is '" + camera_names_[k] +
                                  "' in the calibration, the frame says '" + image.camera + "'");
    write_image(color_path(dir_, k, frame.index), image.color);
    write_image(depth_path(dir_, k, frame.index), image.depth_mm);
    line["cameras"].push_back({{"name", image.camera}, {"timestamp_us", image.timestamp_us}});
  }
  frames_ << line.dump() << "\n";
  frames_.flush();
}

void write_ground_truth(const std::filesystem::path& dir, uint64_t frame, const HostImage& target_rgba,
                        const HostImage& target_depth_m, const HostImage& target_part,
                        const std::vector<HostImage>& camera_parts) {
  const std::filesystem::path gt = dir / "gt";
  write_image(ground_truth_color_path(dir, frame), target_rgba);
  HostImage millimetres(target_depth_m.width, target_depth_m.height, PixelFormat::R16U);
  for (size_t i = 0; i < millimetres.texels.size(); ++i)
    millimetres.texels[i] = std::clamp(std::floor(target_depth_m.texels[i] * 1000.0f + 0.5f), 0.0f, 65535.0f);
  write_image(gt / numbered("target_depth", frame, "png"), millimetres);
  write_image(gt / numbered("target_hand_mask", frame, "png"),
              mask_where(target_part, [](float part) { return part == 2.0f; }));
  for (size_t k = 0; k < camera_parts.size(); ++k)
    write_image(gt / ("cam" + std::to_string(k)) / numbered("foreground", frame, "png"),
                mask_where(camera_parts[k], [](float part) { return part != 0.0f; }));
}

ReplayRgbdSource::ReplayRgbdSource(const std::filesystem::path& dir) : dir_(dir) {
  calibration_ = config::read_json_file(dir_ / "calibration.json");
  const std::string where = "'" + (dir_ / "calibration.json").string() + "'";
  if (config::require_string(calibration_, "format", where) != kRecordingFormat)
    throw config::JsonError(where + ": format is '" + calibration_["format"].get<std::string>() + "', expected '" +
                            kRecordingFormat + "'");
  camera_names_ = camera_names_of(calibration_, where);
  nlohmann::json description = calibration_;
  description.erase("format");
  std::optional<double> recorded_scale;
  if (description.contains("recorded_scale")) {
    recorded_scale = config::require_in_range(description, "recorded_scale", where, 0.01, 4.0);
    description.erase("recorded_scale");
  }
  site_ = site_from_json(description, where);
  for (const RgbdCamera& camera : site_.cameras)
    recorded_.push_back(recorded_scale ? RecordedIntrinsics{scaled_intrinsics(camera.color, *recorded_scale),
                                                            scaled_intrinsics(camera.depth, *recorded_scale)}
                                       : RecordedIntrinsics{camera.color, camera.depth});
  std::ifstream lines(dir_ / "frames.jsonl");
  if (!lines) throw std::runtime_error("cannot read '" + (dir_ / "frames.jsonl").string() + "'");
  std::string line;
  for (size_t number = 1; std::getline(lines, line); ++number) {
    if (line.empty()) continue;
    const std::string at = "'" + (dir_ / "frames.jsonl").string() + "' line " + std::to_string(number);
    try {
      nlohmann::json frame = nlohmann::json::parse(line);
      if (!frame.is_object()) throw config::JsonError(at + ": must be a JSON object");
      config::require_unsigned(frame, "frame", at);
      config::require_unsigned(frame, "timestamp_us", at);
      const nlohmann::json& cameras = config::require_array(frame, "cameras", at);
      if (cameras.size() != camera_names_.size())
        throw config::JsonError(at + ": field 'cameras' must list every camera of the calibration");
      for (size_t k = 0; k < cameras.size(); ++k) {
        const std::string camera_at = at + " cameras[" + std::to_string(k) + "]";
        if (!cameras[k].is_object()) throw config::JsonError(camera_at + ": must be an object");
        if (cameras[k].contains("timestamp_us")) config::require_unsigned(cameras[k], "timestamp_us", camera_at);
      }
      frames_.push_back(std::move(frame));
    } catch (const nlohmann::json::exception& error) {  // also a number too large to read (1E999)
      throw config::JsonError(at + " is not valid JSON: " + error.what());
    }
  }
}

void ReplayRgbdSource::seek(size_t i) {
  if (i > frames_.size())
    throw std::out_of_range("recording '" + dir_.string() + "' has " + std::to_string(frames_.size()) +
                            " frames, cannot seek to " + std::to_string(i));
  next_ = i;
}

std::optional<RgbdFrame> ReplayRgbdSource::next_frame() {
  if (next_ >= frames_.size()) return std::nullopt;
  const nlohmann::json& line = frames_[next_++];
  RgbdFrame frame;
  frame.index = line["frame"].get<uint64_t>();
  frame.timestamp_us = line["timestamp_us"].get<uint64_t>();
  for (size_t k = 0; k < camera_names_.size(); ++k) {
    RgbdImage image;
    image.camera = camera_names_[k];
    image.timestamp_us = line["cameras"][k].value("timestamp_us", frame.timestamp_us);
    const std::filesystem::path color_file = color_path(dir_, k, frame.index);
    const std::filesystem::path depth_file = depth_path(dir_, k, frame.index);
    try {
      check_png_header(color_file, recorded_[k].color.width, recorded_[k].color.height, PngKind::Color8);
      check_png_header(depth_file, recorded_[k].depth.width, recorded_[k].depth.height, PngKind::Depth16);
    } catch (const std::runtime_error& error) {
      throw std::runtime_error(std::string(error.what()) + "; camera '" + camera_names_[k] +
                               "' of calibration.json, whose intrinsics give the recorded size (or its recorded_scale)");
    }
    const HostImage color = read_image(color_file);
    if (color.format != PixelFormat::RGBA32F)
      throw std::runtime_error("color image '" + color_file.string() + "' is not an RGB or RGBA image");
    // PNG color comes back as float RGBA: keep the engine's 8-bit format.
    image.color = HostImage(color.width, color.height, PixelFormat::RGBA8);
    image.color.texels = color.texels;
    image.depth_mm = read_depth_png(depth_file);
    frame.cameras.push_back(std::move(image));
  }
  return frame;
}

}  // namespace rt::sim
