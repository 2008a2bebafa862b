#include "pipeline/demo_layers.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace rt::pipeline {
namespace {

// Coverage of a pixel by a shape given its signed distance in pixels (negative inside).
float coverage(float signed_distance_px) { return std::clamp(0.5f - signed_distance_px, 0.0f, 1.0f); }

float ellipse_distance(float x, float y, float cx, float cy, float rx, float ry) {
  const float nx = (x - cx) / rx, ny = (y - cy) / ry;
  return (std::sqrt(nx * nx + ny * ny) - 1.0f) * std::min(rx, ry);
}

float capsule_distance(float x, float y, float ax, float ay, float bx, float by, float radius) {
  const float px = x - ax, py = y - ay, dx = bx - ax, dy = by - ay;
  const float t = std::clamp((px * dx + py * dy) / (dx * dx + dy * dy), 0.0f, 1.0f);
  return std::hypot(px - t * dx, py - t * dy) - radius;
}

}  // namespace

DemoLayers make_demo_layers(uint32_t width, uint32_t height) {
  DemoLayers layers{HostImage(width, height, PixelFormat::RGBA32F), HostImage(width, height, PixelFormat::RGBA32F),
                    HostImage(width, height, PixelFormat::R32F), HostImage(width, height, PixelFormat::RGBA32F)};
  const float s = float(std::min(width, height));  // shapes scale with the shorter side
  const float cx = 0.5f * float(width);
  for (uint32_t y = 0; y < height; ++y)
    for (uint32_t x = 0; x < width; ++x) {
      const float px = float(x) + 0.5f, py = float(y) + 0.5f;
      // Background: a wall gradient with a faint tile pattern.
      const bool tile = (int(px / (0.08f * s)) + int(py / (0.08f * s))) % 2 == 0;
      const float wall = 0.55f + 0.25f * py / float(height) + (tile ? 0.03f : 0.0f);
      layers.background.at(x, y, 0) = wall * 0.85f;
      layers.background.at(x, y, 1) = wall * 0.9f;
      layers.background.at(x, y, 2) = wall;
      layers.background.at(x, y, 3) = 1.0f;

      // Portrait: head and shoulders, a striped shirt.
      const float head = ellipse_distance(px, py, cx, 0.32f * s, 0.11f * s, 0.14f * s);
      const float torso = ellipse_distance(px, py, cx, 1.05f * s, 0.36f * s, 0.5f * s);
      const float body = std::min(head, torso);
      const float a_i = coverage(body);
      const bool stripe = int(py / (0.03f * s)) % 2 == 0;
      const bool is_head = head < torso;
      layers.portrait.at(x, y, 0) = is_head ? 0.86f : (stripe ? 0.2f : 0.85f);
      layers.portrait.at(x, y, 1) = is_head ? 0.66f : (stripe ? 0.3f : 0.8f);
      layers.portrait.at(x, y, 2) = is_head ? 0.55f : (stripe ? 0.6f : 0.7f);
      layers.portrait.at(x, y, 3) = a_i;

      // Hand: palm and five fingers raised towards the screen, right of centre.
      const float hx = cx + 0.45f * s, hy = 0.6f * s;
      float hand = ellipse_distance(px, py, hx, hy, 0.1f * s, 0.12f * s);
      const float finger_angles[5] = {-1.1f, -0.35f, -0.1f, 0.15f, 0.4f};
      const float finger_lengths[5] = {0.13f, 0.17f, 0.19f, 0.18f, 0.14f};
      for (int f = 0; f < 5; ++f) {
        const float angle = finger_angles[f] - std::numbers::pi_v<float> / 2;
        const float base_x = hx + 0.07f * s * std::cos(angle), base_y = hy + 0.09f * s * std::sin(angle);
        const float tip_x = base_x + finger_lengths[f] * s * std::cos(angle);
        const float tip_y = base_y + finger_lengths[f] * s * std::sin(angle);
        hand = std::min(hand, capsule_distance(px, py, base_x, base_y, tip_x, tip_y, 0.022f * s));
      }
      layers.hand_mask.at(x, y) = coverage(hand);
      const float shade = 0.9f + 0.1f * std::clamp((hy - py) / (0.3f * s), -1.0f, 1.0f);
      layers.hand_color.at(x, y, 0) = 0.93f * shade;
      layers.hand_color.at(x, y, 1) = 0.72f * shade;
      layers.hand_color.at(x, y, 2) = 0.6f * shade;
      layers.hand_color.at(x, y, 3) = 1.0f;
    }
  return layers;
}

float demo_hand_distance_m(uint32_t frame, uint32_t frame_count) {
  const float t = frame_count > 1 ? float(frame) / float(frame_count - 1) : 0.5f;
  return 0.5f - 0.45f * std::sin(std::numbers::pi_v<float> * t);
}

}  // namespace rt::pipeline
