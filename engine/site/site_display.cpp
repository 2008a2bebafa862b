#include "site/site_display.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace rt::site {

void label_link_lost(cv::Mat& bgr, const std::string& reason) {
  const double scale = std::max(0.3, bgr.cols / 900.0);
  const int thickness = std::max(1, int(std::lround(scale * 2)));
  auto line = [&](const std::string& text, double y_fraction) {
    cv::putText(bgr, text, cv::Point(int(bgr.cols * 0.04), int(bgr.rows * y_fraction)), cv::FONT_HERSHEY_SIMPLEX, scale,
                cv::Scalar(40, 40, 230), thickness, cv::LINE_AA);
  };
  line("remote site lost - reconnecting", 0.12);
  if (!reason.empty()) line(reason, 0.22);
}

std::string frame_name(uint64_t index) {
  char name[32];
  std::snprintf(name, sizeof name, "frame_%04llu.png", static_cast<unsigned long long>(index));
  return name;
}

HostImage truth_over_background(const HostImage& truth, const HostImage& background) {
  HostImage out(truth.width, truth.height, PixelFormat::RGBA8);
  for (uint32_t y = 0; y < truth.height; ++y)
    for (uint32_t x = 0; x < truth.width; ++x) {
      const float a = std::clamp(truth.at(x, y, 3), 0.0f, 1.0f);
      for (uint32_t c = 0; c < 3; ++c) out.at(x, y, c) = truth.at(x, y, c) + background.at(x, y, c) * (1.0f - a);
      out.at(x, y, 3) = 1.0f;
    }
  return out;
}

cv::Mat to_bgr8(const HostImage& image) {
  cv::Mat bgr(int(image.height), int(image.width), CV_8UC3);
  for (uint32_t y = 0; y < image.height; ++y)
    for (uint32_t x = 0; x < image.width; ++x)
      for (int c = 0; c < 3; ++c)
        bgr.at<cv::Vec3b>(int(y), int(x))[2 - c] =
            uint8_t(std::lround(std::clamp(image.at(x, y, uint32_t(c)), 0.0f, 1.0f) * 255.0f));
  return bgr;
}

HostImage from_bgr8(const cv::Mat& bgr) {
  HostImage image(uint32_t(bgr.cols), uint32_t(bgr.rows), PixelFormat::RGBA8);
  for (uint32_t y = 0; y < image.height; ++y)
    for (uint32_t x = 0; x < image.width; ++x) {
      const cv::Vec3b& pixel = bgr.at<cv::Vec3b>(int(y), int(x));
      for (uint32_t c = 0; c < 3; ++c) image.at(x, y, c) = float(pixel[2 - c]) / 255.0f;
      image.at(x, y, 3) = 1.0f;
    }
  return image;
}

Camera portrait_camera(const net::PortraitMessage& p) {
  Camera camera;
  camera.name = "portrait target view";
  camera.intrinsics.width = p.width;
  camera.intrinsics.height = p.height;
  camera.intrinsics.fx = p.fx;
  camera.intrinsics.fy = p.fy;
  camera.intrinsics.cx = p.cx;
  camera.intrinsics.cy = p.cy;
  camera.camera_from_site = Eigen::Isometry3d(p.camera_from_site);
  return camera;
}

}  // namespace rt::site
