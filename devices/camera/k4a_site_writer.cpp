#include "camera/k4a_site_writer.h"

#include <stdexcept>

namespace rt::camera::k4a {

RecordingConfig recording_config_for(const sim::RgbdCamera& camera, uint32_t fps, int jpeg_quality) {
  const auto color = color_resolution_for_size(camera.color.width, camera.color.height);
  if (!color)
    throw std::invalid_argument("k4a: camera '" + camera.name + "' has colour " + std::to_string(camera.color.width) +
                                "x" + std::to_string(camera.color.height) + ", not a k4a colour resolution (" +
                                color_resolution_sizes() + ")");
  const auto depth = depth_mode_for_size(camera.depth.width, camera.depth.height);
  if (!depth)
    throw std::invalid_argument("k4a: camera '" + camera.name + "' has depth " + std::to_string(camera.depth.width) +
                                "x" + std::to_string(camera.depth.height) + ", not a k4a depth mode (" +
                                depth_mode_sizes() + ")");
  if (!is_frame_rate(fps))
    throw std::invalid_argument("k4a: " + std::to_string(fps) + " fps is not a k4a frame rate (5, 15, 30)");
  if (jpeg_quality < 1 || jpeg_quality > 100) throw std::invalid_argument("k4a: JPEG quality must be in [1, 100]");
  RecordingConfig config;
  config.color_format = ColorFormat::mjpg;
  config.color_resolution = *color;
  config.depth_mode = *depth;
  config.fps = fps;
  config.calibration.depth = depth_sensor_for(camera.depth, *depth);
  config.calibration.color = color_sensor_for(camera.color, *color);
  return config;
}

std::filesystem::path recording_path(const std::filesystem::path& dir, const std::string& camera_name) {
  return dir / (camera_name + ".mkv");
}

SiteWriter::SiteWriter(const std::filesystem::path& dir, const sim::SiteDescription& site, uint32_t fps,
                       int jpeg_quality)
    : jpeg_quality_(jpeg_quality) {
  std::vector<RecordingConfig> configs;
  for (const sim::RgbdCamera& camera : site.cameras) {
    configs.push_back(recording_config_for(camera, fps, jpeg_quality));
    configs.back().serial = site.name + "-" + camera.name;
    configs.back().calibration.serial = configs.back().serial;
  }
  std::filesystem::create_directories(dir);
  for (size_t k = 0; k < site.cameras.size(); ++k)
    writers_.push_back(std::make_unique<RecordingWriter>(recording_path(dir, site.cameras[k].name), configs[k]));
}

void SiteWriter::write_frame(const sim::RgbdFrame& frame) {
  if (frame.cameras.size() != writers_.size())
    throw std::invalid_argument("k4a site: frame " + std::to_string(frame.index) + " has " +
                                std::to_string(frame.cameras.size()) + " cameras, the site " +
                                std::to_string(writers_.size()));
  for (size_t k = 0; k < writers_.size(); ++k) {
    const sim::RgbdImage& image = frame.cameras[k];
    writers_[k]->write_capture(image.timestamp_us, encode_mjpg(image.color, jpeg_quality_), image.depth_mm);
  }
}

void SiteWriter::close() {
  for (auto& writer : writers_) writer->close();
}

}  // namespace rt::camera::k4a
