#pragma once
// Which of a site's RGBD cameras the image-based model uses (paper: 4 of 6, "the two central
// ones and the two on the side opposite the touching hand"): the hand reaching for the glass
// comes too close to the cameras on its own side, and its arm hides the user from them.
#include <Eigen/Core>

#include <cstddef>
#include <string>
#include <vector>

#include "tracking/hand_skeleton.h"

namespace rt::ibr {

enum class TouchingHand { Left, Right };

// Indices into `camera_positions` (site frame): first the `central` cameras nearest the
// vertical centre line (smallest |x|), then the others, those on the side opposite the touching
// hand first, nearest the centre first. Throws if count is 0 or more than there are cameras.
std::vector<size_t> select_cameras(const std::vector<Eigen::Vector3d>& camera_positions, TouchingHand hand,
                                   size_t count, size_t central = 2);

// Indices of the named cameras, in the order given; throws naming an unknown or repeated camera.
std::vector<size_t> cameras_by_name(const std::vector<std::string>& camera_names, const std::vector<std::string>& wanted);

// The hand nearer the screen (smaller z of its palm); the right hand when both are equally near
// or either is not finite.
TouchingHand touching_hand(const HandSkeleton& right, const HandSkeleton& left);

}  // namespace rt::ibr
