#include "calibration/rigid_alignment.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

#include "calibration/calibration_error.h"

namespace rt::calibration {
namespace {

Eigen::Matrix3Xd as_matrix(const std::vector<Eigen::Vector3d>& points) {
  Eigen::Matrix3Xd matrix(3, points.size());
  for (size_t i = 0; i < points.size(); ++i) matrix.col(Eigen::Index(i)) = points[i];
  return matrix;
}

std::string in_millimetres(double metres) { return std::to_string(int(std::lround(metres * 1000.0))) + " mm"; }

}  // namespace

double RigidFit::rms() const {
  if (residuals.empty()) return 0.0;
  double sum = 0.0;
  for (double r : residuals) sum += r * r;
  return std::sqrt(sum / double(residuals.size()));
}

double off_line_spread(const std::vector<Eigen::Vector3d>& points) {
  if (points.size() < 2) return 0.0;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& point : points) centroid += point;
  centroid /= double(points.size());
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const Eigen::Vector3d& point : points) scatter += (point - centroid) * (point - centroid).transpose();
  // The squared distances to the best line through the centroid sum to the two smallest
  // eigenvalues of the scatter matrix (the squared singular values of the centred points). The
  // 3x3 eigensolver compiles in a fraction of the time of an SVD of a 3xN matrix.
  const Eigen::Vector3d eigenvalues =
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(scatter, Eigen::EigenvaluesOnly).eigenvalues();
  return std::sqrt(std::max(0.0, eigenvalues(0) + eigenvalues(1)) / double(points.size()));
}

RigidFit fit_rigid(const std::vector<Eigen::Vector3d>& source, const std::vector<Eigen::Vector3d>& target,
                   const std::string& what, double min_off_line_spread) {
  if (source.size() != target.size())
    throw CalibrationError(what + ": " + std::to_string(source.size()) + " points to map onto " +
                           std::to_string(target.size()));
  if (source.size() < 3)
    throw CalibrationError(what + ": a rigid transform needs at least 3 corresponding points, have " +
                           std::to_string(source.size()));
  for (size_t i = 0; i < source.size(); ++i)
    if (!source[i].allFinite() || !target[i].allFinite())
      throw CalibrationError(what + ": point " + std::to_string(i) + " is not finite");
  for (const auto* points : {&source, &target})
    if (const double spread = off_line_spread(*points); !(spread >= min_off_line_spread))
      throw CalibrationError(what + ": the points lie on a line (they stray " + in_millimetres(spread) +
                             " RMS from it, at least " + in_millimetres(min_off_line_spread) +
                             " is needed), so the rotation about that line is unknown");

  const Eigen::Matrix4d transform = Eigen::umeyama(as_matrix(source), as_matrix(target), false);
  RigidFit fit;
  fit.target_from_source.linear() = transform.topLeftCorner<3, 3>();
  fit.target_from_source.translation() = transform.topRightCorner<3, 1>();
  // Umeyama's sign rule excludes reflections; checked because a reflection fits a mirrored
  // (left-handed) point set perfectly and would silently flip everything mapped through it.
  if (!transform.allFinite() || !(fit.target_from_source.linear().determinant() > 0.5))
    throw CalibrationError(what + ": the alignment did not give a proper rotation");
  for (size_t i = 0; i < source.size(); ++i)
    fit.residuals.push_back((target[i] - fit.target_from_source * source[i]).norm());
  return fit;
}

}  // namespace rt::calibration
