#pragma once
// Every pixel's ray of a camera with OpenCV's distortion, for the passes and tools that need the
// whole image's rays at once (a depth camera's points).
#include <array>
#include <vector>

#include "geometry/camera.h"

namespace rt {

// Where each pixel centre's ray meets the plane z = 1, (x/z, y/z), row by row: the camera's
// distortion undone by OpenCV's iterative solve, run to convergence rather than its default five
// steps, which leave tenths of a pixel on a strong wide-angle lens (a k4a depth camera's). NaN
// where the solve gives no finite answer.
std::vector<std::array<float, 2>> undistorted_pixel_rays(const CameraIntrinsics& intrinsics);
// The same solve for any pixel positions (x, y): each one's (x/z, y/z), NaN where it has none.
std::vector<std::array<double, 2>> undistorted_points(const CameraIntrinsics& intrinsics,
                                                      const std::vector<std::array<double, 2>>& pixels);

}  // namespace rt
