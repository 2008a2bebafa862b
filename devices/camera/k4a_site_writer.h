#pragma once
// A site's RGBD cameras written as k4a recordings, one `<camera name>.mkv` per camera: how the
// simulator's frames reach the same reader as a real installation's. The recordings hold what a
// device stores (images, factory intrinsics, colour-from-depth); where the cameras stand is the
// site description's, as for real cameras.
#include <filesystem>
#include <memory>
#include <vector>

#include "camera/k4a_recording_writer.h"
#include "sim/rgbd_source.h"
#include "sim/site_description.h"

namespace rt::camera::k4a {

// The recording configuration of a camera whose images have exactly a k4a mode's sizes (colour
// and depth, both in the same pose: colour-from-depth is the identity). Throws
// std::invalid_argument naming the camera, its sizes and the modes when they match none.
RecordingConfig recording_config_for(const sim::RgbdCamera& camera, uint32_t fps, int jpeg_quality);

// Where camera `name`'s recording lives in a site's folder.
std::filesystem::path recording_path(const std::filesystem::path& dir, const std::string& camera_name);

class SiteWriter {
 public:
  // Checks every camera first (nothing is created when one has no k4a mode); serials are
  // "<site name>-<camera name>".
  SiteWriter(const std::filesystem::path& dir, const sim::SiteDescription& site, uint32_t fps, int jpeg_quality);
  // Colour as MJPG at the quality, depth as recorded; each camera's capture at its own time.
  void write_frame(const sim::RgbdFrame& frame);
  void close();

 private:
  std::vector<std::unique_ptr<RecordingWriter>> writers_;
  int jpeg_quality_;
};

}  // namespace rt::camera::k4a
