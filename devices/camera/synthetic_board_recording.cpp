#include "camera/synthetic_board_recording.h"

#include <opencv2/core.hpp>

#include <cstdint>

#include "calibration/synthetic_board_image.h"
#include "camera/k4a_site_writer.h"

namespace rt::camera {
namespace {

constexpr uint64_t kBoardHeldUs = 1000000;

// The depth camera records nothing of a flat board worth having; an image of the smallest k4a
// depth mode, no surface anywhere, keeps the recording a valid one.
CameraIntrinsics empty_depth_camera() {
  CameraIntrinsics depth;
  depth.width = 320;
  depth.height = 288;
  depth.fx = depth.fy = 252.0;
  depth.cx = 159.5;
  depth.cy = 143.5;
  return depth;
}

HostImage rgba_of(const cv::Mat& gray) {
  HostImage rgba(uint32_t(gray.cols), uint32_t(gray.rows), PixelFormat::RGBA8);
  for (int y = 0; y < gray.rows; ++y)
    for (int x = 0; x < gray.cols; ++x) {
      const float level = float(gray.at<uint8_t>(y, x)) / 255.0f;
      for (uint32_t c = 0; c < 3; ++c) rgba.at(uint32_t(x), uint32_t(y), c) = level;
      rgba.at(uint32_t(x), uint32_t(y), 3) = 1.0f;
    }
  return rgba;
}

}  // namespace

void write_board_recording(const calibration::SyntheticSite& site, const std::filesystem::path& dir, int jpeg_quality) {
  sim::SiteDescription recorded = site.truth;
  for (sim::RgbdCamera& camera : recorded.cameras) camera.depth = empty_depth_camera();
  k4a::SiteWriter writer(dir, recorded, 30, jpeg_quality);
  sim::write_site(dir / "site.json", recorded);
  for (size_t view = 0; view < site.site_from_board.size(); ++view) {
    sim::RgbdFrame frame;
    frame.index = view;
    frame.timestamp_us = view * kBoardHeldUs;
    for (const sim::RgbdCamera& camera : recorded.cameras) {
      sim::RgbdImage image;
      image.camera = camera.name;
      image.timestamp_us = frame.timestamp_us;
      image.color = rgba_of(calibration::render_chessboard(
          camera.color, camera.camera_from_site * site.site_from_board[view], site.extrinsics_input.board));
      image.depth_mm = HostImage(camera.depth.width, camera.depth.height, PixelFormat::R16U);
      frame.cameras.push_back(std::move(image));
    }
    writer.write_frame(frame);
  }
  writer.close();
}

}  // namespace rt::camera
