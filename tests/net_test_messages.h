#pragma once
// Messages for the network tests: every field set to something a mix-up would change.
#include <cmath>
#include <random>

#include "net/messages.h"
#include "support/hands.h"

namespace rt::test {

inline net::PortraitMessage test_portrait(uint32_t width, uint32_t height, uint64_t frame, uint32_t seed = 1) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  net::PortraitMessage p;
  p.frame_index = frame;
  p.capture_timestamp_us = 1'000'000 + frame * 33'333;
  p.width = width;
  p.height = height;
  p.fx = 612.5;
  p.fy = 611.25;
  p.cx = width * 0.5 + 3.25;
  p.cy = height * 0.5 - 120.125;  // the target view's principal point is shifted
  p.camera_from_site = Eigen::Matrix4d::Identity();
  p.camera_from_site.topLeftCorner<3, 3>() = Eigen::AngleAxisd(0.3, Eigen::Vector3d(0.2, 1, 0).normalized()).toRotationMatrix();
  p.camera_from_site.col(3).head<3>() = Eigen::Vector3d(0.01, -0.02, 0.7);
  p.color = HostImage(width, height, PixelFormat::RGBA32F);
  p.depth = HostImage(width, height, PixelFormat::R32F);
  for (uint32_t y = 0; y < height; ++y)
    for (uint32_t x = 0; x < width; ++x) {
      // Smooth color (what a portrait looks like to JPEG) with a little noise.
      const float u = float(x) / float(width), v = float(y) / float(height);
      p.color.at(x, y, 0) = 0.5f + 0.4f * std::sin(6.0f * u + float(frame)) + 0.01f * unit(random);
      p.color.at(x, y, 1) = 0.3f + 0.5f * v;
      p.color.at(x, y, 2) = 0.2f + 0.3f * u * v;
      // Alpha: outside, inside, and an edge of arbitrary floats.
      const float r = std::hypot(u - 0.5f, v - 0.5f);
      p.color.at(x, y, 3) = r > 0.4f ? 0.0f : r < 0.3f ? 1.0f : unit(random);
      p.depth.at(x, y) = r > 0.4f ? 0.0f : 0.6f + 0.2f * unit(random);
    }
  return p;
}

inline net::SkeletonMessage test_skeleton(uint64_t timestamp_us) {
  net::SkeletonMessage s;
  s.timestamp_us = timestamp_us;
  HandSkeleton right = flat_hand(0.1, 0.05, 0.12, timestamp_us - 5);
  right.id = 7;
  right.confidence = 0.875f;
  right.elbow.setConstant(std::nan(""));  // a tracker frame without an elbow or widths
  HandSkeleton left = flat_hand(-0.2, -0.01, 0.3, timestamp_us - 9);
  left.id = -3;
  left.is_left = true;
  left.confidence = 0.5f;
  left.elbow = {-0.3, -0.35, 0.45};
  left.palm_width_m = 0.0815;
  left.arm_width_m = 0.064;
  s.hands = {right, left};
  return s;
}

}  // namespace rt::test
