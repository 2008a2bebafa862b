#pragma once
// Pieces the rasterizers' C++ references share (person_raster, hand_raster): clipping a polygon
// against one plane in clip space, and the distance of a pixel to a drawn edge.
#include <Eigen/Core>

#include <algorithm>
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

}  // namespace rt::passes
