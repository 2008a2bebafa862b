#pragma once
// The viewer's eyes from RGBD views: triangulated where two or more views see both eyes, else
// the one view that does places them in 3D with its own depth image. A stand whose other cameras
// see the seated viewer from the corners (about 50 degrees aside) or from below, as the default
// site's does, gives the frontal-face cascade one view only; an RGBD camera still knows how far
// the eyes are.
#include <opencv2/core.hpp>

#include <span>

#include "geometry/camera.h"
#include "image/host_image.h"
#include "viewer/eye_detector.h"
#include "viewer/eye_pair.h"

namespace rt {

// The surface point seen through `pixel` of the color camera: the first point along its ray
// (0.2 to 3 m) that lies on or behind the depth image's surface (r16ui millimetres, 0 = invalid)
// as the depth camera sees it. Empty where the ray meets no valid depth.
std::optional<Eigen::Vector3d> surface_along_ray(const Camera& color, const Camera& depth, const HostImage& depth_mm,
                                                 const Eigen::Vector2d& pixel);

// locate_viewer_eyes (eye_locator.h) with depth: `depth_cameras` and `depth_images` match the
// color ones (empty spans: no depth, as locate_viewer_eyes). With fewer than two views seeing
// both eyes, the first that does is placed by its depth; the pair's limits still apply.
EyePair locate_viewer_eyes_rgbd(EyeDetector& detector, std::span<const Camera> cameras, std::span<const cv::Mat> images,
                                std::span<const Camera> depth_cameras, std::span<const HostImage> depth_images,
                                const EyePairLimits& limits = {});

}  // namespace rt
