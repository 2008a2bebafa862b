#include "ibr/camera_selection.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

namespace rt::ibr {

std::vector<size_t> select_cameras(const std::vector<Eigen::Vector3d>& positions, TouchingHand hand, size_t count,
                                   size_t central) {
  if (count == 0 || count > positions.size())
    throw std::invalid_argument("camera selection: asked for " + std::to_string(count) + " of " +
                                std::to_string(positions.size()) + " cameras");
  for (const auto& position : positions)
    if (!position.allFinite()) throw std::invalid_argument("camera selection: a camera position is not finite");
  std::vector<size_t> order(positions.size());
  std::iota(order.begin(), order.end(), size_t(0));
  auto by_centre = [&](size_t a, size_t b) {
    return std::abs(positions[a].x()) < std::abs(positions[b].x()) ||
           (std::abs(positions[a].x()) == std::abs(positions[b].x()) && a < b);
  };
  std::stable_sort(order.begin(), order.end(), by_centre);
  const size_t centre_count = std::min(central, positions.size());
  // The side opposite the hand: x < 0 for the right hand (site +x is the user's right).
  const double opposite_sign = hand == TouchingHand::Right ? -1.0 : 1.0;
  std::stable_partition(order.begin() + std::ptrdiff_t(centre_count), order.end(),
                        [&](size_t i) { return positions[i].x() * opposite_sign > 0.0; });
  order.resize(count);
  return order;
}

std::vector<size_t> cameras_by_name(const std::vector<std::string>& names, const std::vector<std::string>& wanted) {
  std::vector<size_t> indices;
  for (const std::string& name : wanted) {
    const auto found = std::find(names.begin(), names.end(), name);
    if (found == names.end()) {
      std::string known;
      for (const auto& n : names) known += (known.empty() ? "" : ", ") + n;
      throw std::invalid_argument("no camera named '" + name + "' (cameras: " + known + ")");
    }
    const size_t index = size_t(found - names.begin());
    if (std::find(indices.begin(), indices.end(), index) != indices.end())
      throw std::invalid_argument("camera '" + name + "' is named twice");
    indices.push_back(index);
  }
  if (indices.empty()) throw std::invalid_argument("no cameras named");
  return indices;
}

TouchingHand touching_hand(const HandSkeleton& right, const HandSkeleton& left) {
  const double right_z = right.palm.z(), left_z = left.palm.z();
  if (!std::isfinite(right_z) || !std::isfinite(left_z)) return std::isfinite(left_z) ? TouchingHand::Left : TouchingHand::Right;
  return left_z < right_z ? TouchingHand::Left : TouchingHand::Right;
}

}  // namespace rt::ibr
