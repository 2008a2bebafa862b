#pragma once
// A calibrated camera, OpenCV's pinhole convention (x right, y down, z forward) with its
// Brown-Conrady / rational distortion, and its pose as a camera-from-site rigid transform
// (DESIGN.md section 2). Read from and written to the camera JSON of the calibration.
#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include <array>
#include <optional>
#include <string>

namespace rt {

struct Distortion {
  // OpenCV's order: k1, k2, p1, p2, k3, k4, k5, k6.
  double k1 = 0, k2 = 0, p1 = 0, p2 = 0, k3 = 0, k4 = 0, k5 = 0, k6 = 0;
  std::array<double, 8> as_opencv() const { return {k1, k2, p1, p2, k3, k4, k5, k6}; }
  static Distortion from_opencv(const double* coefficients, size_t count);
};

struct CameraIntrinsics {
  uint32_t width = 0, height = 0;  // pixels
  double fx = 0, fy = 0, cx = 0, cy = 0;
  Distortion distortion;
};

struct Camera {
  std::string name;
  CameraIntrinsics intrinsics;
  Eigen::Isometry3d camera_from_site = Eigen::Isometry3d::Identity();

  Eigen::Vector3d position_in_site() const { return camera_from_site.inverse().translation(); }
  // Pixel of a site-frame point, distortion applied; empty for points at or behind the camera.
  std::optional<Eigen::Vector2d> project(const Eigen::Vector3d& site_point) const;
  // Unit ray in the site frame through a (distorted) pixel, from the camera centre.
  Eigen::Vector3d ray_in_site(const Eigen::Vector2d& pixel) const;
};

// The intrinsics of the same camera at `scale` times its resolution (a scene's resolution
// scale, a supersampled view): the principal point moves with the pixels. Throws
// std::invalid_argument unless scale > 0.
CameraIntrinsics scaled_intrinsics(const CameraIntrinsics& intrinsics, double scale);

// JSON: {"name", "width", "height", "fx", "fy", "cx", "cy", "distortion": {"k1", ...},
// "camera_from_site": 4x4 row-major (optional)}. Errors name the camera and the field.
nlohmann::json intrinsics_to_json(const CameraIntrinsics& intrinsics);
CameraIntrinsics intrinsics_from_json(const nlohmann::json& json, const std::string& where);
nlohmann::json camera_to_json(const Camera& camera);
Camera camera_from_json(const nlohmann::json& json);

nlohmann::json isometry_to_json(const Eigen::Isometry3d& transform);
// Checks that the rotation part is a rotation (orthonormal, det +1) within 1e-6.
Eigen::Isometry3d isometry_from_json(const nlohmann::json& json, const std::string& where);

}  // namespace rt
