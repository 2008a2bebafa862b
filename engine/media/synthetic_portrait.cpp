#include "media/synthetic_portrait.h"

#include <algorithm>
#include <cmath>
#include <random>

namespace rt::media {

net::PortraitMessage synthetic_portrait(uint32_t width, uint32_t height, uint64_t frame) {
  std::mt19937 random(uint32_t(frame) * 7919u + 1u);
  std::normal_distribution<float> noise(0.0f, 1.0f);
  net::PortraitMessage p;
  p.frame_index = frame;
  p.width = width;
  p.height = height;
  p.fx = p.fy = 0.9 * width;
  p.cx = width / 2.0;
  p.cy = height / 2.0 - 0.1 * height;
  p.color = HostImage(width, height, PixelFormat::RGBA32F);
  p.depth = HostImage(width, height, PixelFormat::R32F);
  const float sway = 0.03f * std::sin(float(frame) * 0.2f);
  const float lift = 0.05f * std::sin(float(frame) * 0.13f);
  const float edge = 1.5f / float(height);  // about a pixel and a half of soft alpha
  for (uint32_t y = 0; y < height; ++y)
    for (uint32_t x = 0; x < width; ++x) {
      const float u = (float(x) / float(width) - 0.5f - sway) * float(width) / float(height);
      const float v = float(y) / float(height) - 0.55f;
      // Signed distances (in image heights, negative inside) of a head, a torso and a forearm.
      const float head = (std::hypot(u / 0.13f, (v + 0.2f) / 0.17f) - 1.0f) * 0.13f;
      const float body = (std::hypot(u / 0.32f, (v - 0.35f) / 0.4f) - 1.0f) * 0.32f;
      const float ax = u - 0.42f, ay = v + 0.05f + lift;
      const float arm = std::max(std::abs(ax) - 0.05f, std::abs(ay - 0.15f) - 0.2f);
      const float inside = std::min({head, body, arm});
      const float alpha = std::clamp(0.5f - inside / edge, 0.0f, 1.0f);
      p.color.at(x, y, 3) = alpha;
      if (alpha == 0.0f) continue;
      const bool on_arm = arm <= std::min(head, body);
      const float shade = 0.03f * std::sin(40.0f * u) + 0.02f * std::sin(23.0f * v + 3.0f * u);
      p.color.at(x, y, 0) = std::clamp(0.62f + 0.2f * v + shade + 0.008f * noise(random), 0.0f, 1.0f);
      p.color.at(x, y, 1) = std::clamp((on_arm ? 0.5f : 0.42f) + 0.1f * u + 0.008f * noise(random), 0.0f, 1.0f);
      p.color.at(x, y, 2) = std::clamp(0.35f + 0.05f * std::cos(30.0f * v) + 0.008f * noise(random), 0.0f, 1.0f);
      // The forearm reaches toward the camera (the glass); the body is rounded.
      const float rounded = on_arm ? 1.05f - 0.3f * (ay - 0.15f) : 1.5f - 0.6f * std::min(-inside, 0.3f);
      p.depth.at(x, y) = rounded + 0.001f * noise(random);
    }
  return p;
}

}  // namespace rt::media
