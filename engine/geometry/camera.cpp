#include "geometry/camera.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>

#include "config/json.h"

namespace rt {

CameraIntrinsics scaled_intrinsics(const CameraIntrinsics& k, double scale) {
  if (!(scale > 0) || !std::isfinite(scale)) throw std::invalid_argument("resolution scale must be > 0");
  CameraIntrinsics out = k;
  out.width = std::max<uint32_t>(1, uint32_t(std::lround(k.width * scale)));
  out.height = std::max<uint32_t>(1, uint32_t(std::lround(k.height * scale)));
  const double sx = double(out.width) / k.width, sy = double(out.height) / k.height;
  out.fx = k.fx * sx;
  out.fy = k.fy * sy;
  // Pixel centres: OpenCV's pixel (0, 0) covers [-0.5, 0.5], so scale about the image corner.
  out.cx = (k.cx + 0.5) * sx - 0.5;
  out.cy = (k.cy + 0.5) * sy - 0.5;
  return out;
}

Distortion Distortion::from_opencv(const double* c, size_t count) {
  Distortion d;
  double* fields[] = {&d.k1, &d.k2, &d.p1, &d.p2, &d.k3, &d.k4, &d.k5, &d.k6};
  for (size_t i = 0; i < std::min<size_t>(count, 8); ++i) *fields[i] = c[i];
  return d;
}

namespace {

cv::Matx33d camera_matrix(const CameraIntrinsics& k) { return {k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1}; }

}  // namespace

std::optional<Eigen::Vector2d> Camera::project(const Eigen::Vector3d& site_point) const {
  const Eigen::Vector3d p = camera_from_site * site_point;
  if (!(p.z() > 1e-9) || !p.allFinite()) return std::nullopt;
  const std::vector<cv::Point3d> object{{p.x(), p.y(), p.z()}};
  std::vector<cv::Point2d> image;
  const auto coefficients = intrinsics.distortion.as_opencv();
  cv::projectPoints(object, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), camera_matrix(intrinsics),
                    cv::Mat(coefficients.size(), 1, CV_64F, const_cast<double*>(coefficients.data())), image);
  return Eigen::Vector2d(image[0].x, image[0].y);
}

Eigen::Vector3d Camera::ray_in_site(const Eigen::Vector2d& pixel) const {
  const std::vector<cv::Point2d> distorted{{pixel.x(), pixel.y()}};
  std::vector<cv::Point2d> normalised;
  const auto coefficients = intrinsics.distortion.as_opencv();
  cv::undistortPoints(distorted, normalised, camera_matrix(intrinsics),
                      cv::Mat(coefficients.size(), 1, CV_64F, const_cast<double*>(coefficients.data())));
  const Eigen::Vector3d ray_camera(normalised[0].x, normalised[0].y, 1.0);
  return (camera_from_site.linear().transpose() * ray_camera).normalized();
}

nlohmann::json intrinsics_to_json(const CameraIntrinsics& k) {
  const Distortion& d = k.distortion;
  return {{"width", k.width}, {"height", k.height}, {"fx", k.fx}, {"fy", k.fy}, {"cx", k.cx}, {"cy", k.cy},
          {"distortion", {{"k1", d.k1}, {"k2", d.k2}, {"p1", d.p1}, {"p2", d.p2}, {"k3", d.k3}, {"k4", d.k4},
                          {"k5", d.k5}, {"k6", d.k6}}}};
}

CameraIntrinsics intrinsics_from_json(const nlohmann::json& json, const std::string& where) {
  using namespace config;
  CameraIntrinsics k;
  k.width = uint32_t(require_positive(json, "width", where));
  k.height = uint32_t(require_positive(json, "height", where));
  k.fx = require_positive(json, "fx", where);
  k.fy = require_positive(json, "fy", where);
  k.cx = require_number(json, "cx", where);
  k.cy = require_number(json, "cy", where);
  if (json.contains("distortion")) {
    const nlohmann::json& d = json["distortion"];
    const std::string inner = where + " distortion";
    if (!d.is_object()) throw JsonError(inner + ": must be an object with k1, k2, p1, p2[, k3, k4, k5, k6]");
    for (const auto& [key, value] : d.items()) {
      static const char* known[] = {"k1", "k2", "p1", "p2", "k3", "k4", "k5", "k6"};
      if (std::find(std::begin(known), std::end(known), key) == std::end(known))
        throw JsonError(inner + ": unknown coefficient '" + key + "' (known: k1 k2 p1 p2 k3 k4 k5 k6)");
      (void)value;
    }
    auto coefficient = [&](const char* name) { return d.contains(name) ? require_number(d, name, inner) : 0.0; };
    k.distortion = {coefficient("k1"), coefficient("k2"), coefficient("p1"), coefficient("p2"),
                    coefficient("k3"), coefficient("k4"), coefficient("k5"), coefficient("k6")};
  }
  return k;
}

nlohmann::json isometry_to_json(const Eigen::Isometry3d& transform) {
  nlohmann::json rows = nlohmann::json::array();
  for (int r = 0; r < 4; ++r) rows.push_back({transform(r, 0), transform(r, 1), transform(r, 2), transform(r, 3)});
  return rows;
}

Eigen::Isometry3d isometry_from_json(const nlohmann::json& json, const std::string& where) {
  using config::JsonError;
  if (!json.is_array() || json.size() != 4) throw JsonError(where + ": must be a 4x4 matrix (4 rows of 4 numbers)");
  Eigen::Matrix4d matrix;
  for (int r = 0; r < 4; ++r) {
    if (!json[r].is_array() || json[r].size() != 4) throw JsonError(where + ": row " + std::to_string(r) + " must have 4 numbers");
    for (int c = 0; c < 4; ++c) {
      if (!json[r][c].is_number()) throw JsonError(where + ": entry (" + std::to_string(r) + ", " + std::to_string(c) + ") is not a number");
      matrix(r, c) = json[r][c].get<double>();
    }
  }
  if (!matrix.allFinite()) throw JsonError(where + ": holds a non-finite number");
  if ((matrix.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).norm() > 1e-9) throw JsonError(where + ": last row must be 0 0 0 1");
  const Eigen::Matrix3d rotation = matrix.topLeftCorner<3, 3>();
  if ((rotation * rotation.transpose() - Eigen::Matrix3d::Identity()).norm() > 1e-6 || rotation.determinant() < 0)
    throw JsonError(where + ": the 3x3 part is not a rotation (orthonormal with determinant +1)");
  Eigen::Isometry3d transform = Eigen::Isometry3d::Identity();
  transform.linear() = rotation;
  transform.translation() = matrix.topRightCorner<3, 1>();
  return transform;
}

nlohmann::json camera_to_json(const Camera& camera) {
  nlohmann::json json = intrinsics_to_json(camera.intrinsics);
  json["name"] = camera.name;
  json["camera_from_site"] = isometry_to_json(camera.camera_from_site);
  return json;
}

Camera camera_from_json(const nlohmann::json& json) {
  Camera camera;
  camera.name = config::require_string(json, "name", "camera");
  const std::string where = "camera '" + camera.name + "'";
  camera.intrinsics = intrinsics_from_json(json, where);
  if (json.contains("camera_from_site"))
    camera.camera_from_site = isometry_from_json(json["camera_from_site"], where + " camera_from_site");
  return camera;
}

}  // namespace rt
