#pragma once
// Pieces the rasterizers' C++ references share (person_raster, hand_raster): clipping a polygon
// against one plane in clip space, and the distance of a pixel to a drawn edge.
#include <Eigen/Core>

#include <algorithm>
#include <array>
#include <optional>
#include <cmath>
#include <cstdint>
#include <vector>

namespace rt::passes {

// Sutherland-Hodgman against one clip plane, given as distance(v) >= 0 inside. The vertex type
// brings its own `lerp(a, b, t)` (found by argument-dependent lookup).
template <typename Vertex, typename Distance>
std::vector<Vertex> clip_polygon(const std::vector<Vertex>& polygon, Distance distance) {
  std::vector<Vertex> out;
  for (size_t i = 0; i < polygon.size(); ++i) {
    const Vertex& a = polygon[i];
    const Vertex& b = polygon[(i + 1) % polygon.size()];
    const double da = distance(a), db = distance(b);
    if (da >= 0) out.push_back(a);
    if ((da >= 0) != (db >= 0)) out.push_back(lerp(a, b, da / (da - db)));
  }
  return out;
}

inline double distance_to_segment(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double length2 = ab.squaredNorm();
  const double t = length2 > 0 ? std::clamp((p - a).dot(ab) / length2, 0.0, 1.0) : 0.0;
  return (p - (a + t * ab)).norm();
}

// Visits every pixel in the bounding box (one pixel wider) of the screen-space triangle a, b, c,
// clipped to the image, as visit(x, y, pixel_centre, w0, w1, w2) with the barycentric weights
// at the pixel's centre (x + 0.5, y + 0.5): all three >= 0 inside. Returns false, visiting
// nothing, for a degenerate triangle (Vulkan draws nothing then).
template <typename Visit>
bool for_each_pixel_near_triangle(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c,
                                  uint32_t width, uint32_t height, Visit visit) {
  const double area = (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
  if (std::abs(area) < 1e-12) return false;
  const int x0 = std::max(0, int(std::floor(std::min({a.x(), b.x(), c.x()}))) - 1);
  const int x1 = std::min(int(width) - 1, int(std::ceil(std::max({a.x(), b.x(), c.x()}))) + 1);
  const int y0 = std::max(0, int(std::floor(std::min({a.y(), b.y(), c.y()}))) - 1);
  const int y1 = std::min(int(height) - 1, int(std::ceil(std::max({a.y(), b.y(), c.y()}))) + 1);
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x) {
      const Eigen::Vector2d p(x + 0.5, y + 0.5);
      const double w0 = ((b - p).x() * (c - p).y() - (b - p).y() * (c - p).x()) / area;
      const double w1 = ((c - p).x() * (a - p).y() - (c - p).y() * (a - p).x()) / area;
      visit(x, y, p, w0, w1, 1.0 - w0 - w1);
    }
  return true;
}

// Inside the triangle (all screen weights >= 0), the LESS depth test against `stored` (updated
// when it passes), then the perspective-correct weights from the vertices' clip w. Empty when the
// pixel is outside the triangle or behind what is already drawn.
inline std::optional<std::array<double, 3>> depth_tested_weights(const std::array<double, 3>& screen_weights,
                                                                 const std::array<double, 3>& depths,
                                                                 const std::array<double, 3>& clip_w, double& stored) {
  const auto& w = screen_weights;
  if (w[0] < 0 || w[1] < 0 || w[2] < 0) return std::nullopt;
  const double z = w[0] * depths[0] + w[1] * depths[1] + w[2] * depths[2];
  if (!(z < stored)) return std::nullopt;
  stored = z;
  const std::array<double, 3> p{w[0] / clip_w[0], w[1] / clip_w[1], w[2] / clip_w[2]};
  const double sum = p[0] + p[1] + p[2];
  return std::array<double, 3>{p[0] / sum, p[1] / sum, p[2] / sum};
}

}  // namespace rt::passes
