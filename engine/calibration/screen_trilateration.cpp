#include "calibration/screen_trilateration.h"

#include <Eigen/QR>
#include <unsupported/Eigen/LevenbergMarquardt>

#include <cmath>

#include "calibration/calibration_error.h"

namespace rt::calibration {

const char* corner_name(ScreenCorner corner) {
  switch (corner) {
    case ScreenCorner::TopLeft: return "top_left";
    case ScreenCorner::TopRight: return "top_right";
    case ScreenCorner::BottomRight: return "bottom_right";
    case ScreenCorner::BottomLeft: return "bottom_left";
  }
  return "?";
}

Eigen::Vector3d corner_position(const Screen& screen, ScreenCorner corner) {
  const double x = screen.width_m / 2, y = screen.height_m / 2;
  switch (corner) {
    case ScreenCorner::TopLeft: return {-x, y, 0};
    case ScreenCorner::TopRight: return {x, y, 0};
    case ScreenCorner::BottomRight: return {x, -y, 0};
    case ScreenCorner::BottomLeft: return {-x, -y, 0};
  }
  return Eigen::Vector3d::Zero();
}

namespace {

// r_i = |p - a_i| - d_i: the distance errors themselves, which the linear system (whose
// equations are differences of squares) weighs unevenly.
struct DistanceResiduals : Eigen::DenseFunctor<double> {
  std::array<Eigen::Vector3d, 4> corners;
  CornerDistances distances;

  DistanceResiduals(const std::array<Eigen::Vector3d, 4>& corners_in, const CornerDistances& distances_in)
      : DenseFunctor(3, 4), corners(corners_in), distances(distances_in) {}
  int operator()(const InputType& p, ValueType& residuals) const {
    for (int i = 0; i < 4; ++i) residuals(i) = (Eigen::Vector3d(p) - corners[size_t(i)]).norm() - distances[size_t(i)];
    return 0;
  }
  int df(const InputType& p, JacobianType& jacobian) const {
    for (int i = 0; i < 4; ++i) {
      const Eigen::Vector3d offset = Eigen::Vector3d(p) - corners[size_t(i)];
      const double length = std::max(offset.norm(), 1e-12);
      jacobian.row(i) = (offset / length).transpose();
    }
    return 0;
  }
};

}  // namespace

Trilateration trilaterate(const CornerDistances& distances, const Screen& screen, const std::string& camera,
                          double max_residual_m) {
  const std::string where = "camera '" + camera + "'";
  for (ScreenCorner corner : kScreenCorners)
    if (const double d = distances[size_t(corner)]; !std::isfinite(d) || d <= 0.0)
      throw CalibrationError(where + ": the distance to the " + corner_name(corner) +
                             " screen corner must be a positive number of metres");
  // |p - a|^2 = d^2 is linear in (x, y, w = |p|^2) when every corner a has z = 0:
  // -2 a_x x - 2 a_y y + w = d^2 - |a|^2. Four corners, three unknowns.
  Eigen::Matrix<double, 4, 3> system;
  Eigen::Vector4d right;
  for (ScreenCorner corner : kScreenCorners) {
    const Eigen::Vector3d a = corner_position(screen, corner);
    const double d = distances[size_t(corner)];
    system.row(int(corner)) << -2 * a.x(), -2 * a.y(), 1.0;
    right(int(corner)) = d * d - a.squaredNorm();
  }
  const Eigen::Vector3d solution = system.colPivHouseholderQr().solve(right);
  const double x = solution(0), y = solution(1);
  const double z_squared = solution(2) - x * x - y * y;
  // A slightly negative z^2 is noise on a camera near the screen plane. The linear estimate
  // then starts a Levenberg-Marquardt refinement of the distance errors; it starts off the
  // plane, where the z derivative vanishes.
  std::array<Eigen::Vector3d, 4> corners;
  for (ScreenCorner corner : kScreenCorners) corners[size_t(corner)] = corner_position(screen, corner);
  DistanceResiduals residuals(corners, distances);
  Eigen::LevenbergMarquardt<DistanceResiduals> solver(residuals);
  Eigen::VectorXd position(3);
  position << x, y, std::max(std::sqrt(std::max(z_squared, 0.0)), 0.01);
  solver.minimize(position);
  // The mirror image through the screen plane fits as well; the cameras are in front.
  Trilateration result;
  result.position_in_site = {position(0), position(1), std::abs(position(2))};
  double worst = 0.0;
  ScreenCorner worst_corner = ScreenCorner::TopLeft;
  for (ScreenCorner corner : kScreenCorners) {
    const double residual =
        (result.position_in_site - corner_position(screen, corner)).norm() - distances[size_t(corner)];
    result.residuals_m[size_t(corner)] = residual;
    if (!std::isfinite(residual) || std::abs(residual) > worst) {
      worst = std::abs(residual);
      worst_corner = corner;
    }
  }
  if (!result.position_in_site.allFinite() || !(worst <= max_residual_m))
    throw CalibrationError(where + ": the distances to the screen corners are inconsistent: no point lies within " +
                           std::to_string(int(std::lround(max_residual_m * 1000))) + " mm of all four (the " +
                           corner_name(worst_corner) + " distance is off by " +
                           std::to_string(int(std::lround(worst * 1000))) +
                           " mm); re-measure, and check that each distance goes with its corner as the seated "
                           "user sees the screen");
  return result;
}

}  // namespace rt::calibration
