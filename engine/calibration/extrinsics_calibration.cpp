#include "calibration/extrinsics_calibration.h"

#include <cmath>

#include "calibration/calibration_error.h"

namespace rt::calibration {
namespace {

std::string millimetres(double metres) { return std::to_string(int(std::lround(metres * 1000.0))) + " mm"; }

constexpr size_t kMinCamerasToPlace = 3;

}  // namespace

ExtrinsicsResult calibrate_extrinsics(const ExtrinsicsInput& input, const ExtrinsicsLimits& limits) {
  if (input.cameras.size() < kMinCamerasToPlace)
    throw CalibrationError("placing the cameras in the site frame needs at least " +
                           std::to_string(kMinCamerasToPlace) +
                           " cameras (not on one line) with measured screen-corner distances, have " +
                           std::to_string(input.cameras.size()));
  std::vector<NamedIntrinsics> intrinsics;
  for (const CameraSetup& camera : input.cameras) intrinsics.push_back({camera.name, camera.intrinsics});
  const std::vector<CameraLink> links =
      link_cameras(intrinsics, input.snapshots, input.board, input.reference_camera, limits.max_link_rms_px);

  ExtrinsicsResult result;
  std::vector<Eigen::Vector3d> in_reference, in_site;
  for (size_t i = 0; i < input.cameras.size(); ++i) {
    PlacedCamera placed;
    placed.camera.name = input.cameras[i].name;
    placed.camera.intrinsics = input.cameras[i].intrinsics;
    placed.link = links[i];
    placed.trilateration = trilaterate(input.cameras[i].corner_distances_m, input.screen, input.cameras[i].name,
                                       limits.max_corner_distance_residual_m);
    in_reference.push_back(links[i].camera_from_reference.inverse().translation());
    in_site.push_back(placed.trilateration.position_in_site);
    result.cameras.push_back(std::move(placed));
  }

  const RigidFit alignment =
      fit_rigid(in_reference, in_site, "the cameras' positions (from the chessboard views and the distances)");
  const Eigen::Isometry3d reference_from_site = alignment.target_from_source.inverse();
  result.alignment_rms_m = alignment.rms();
  for (size_t i = 0; i < result.cameras.size(); ++i) {
    PlacedCamera& placed = result.cameras[i];
    placed.alignment_residual_m = alignment.residuals[i];
    placed.camera.camera_from_site = placed.link.camera_from_reference * reference_from_site;
    if (!(placed.alignment_residual_m <= limits.max_alignment_residual_m))
      throw CalibrationError("camera '" + placed.camera.name + "' lies " + millimetres(placed.alignment_residual_m) +
                             " from where its screen-corner distances put it (at most " +
                             millimetres(limits.max_alignment_residual_m) +
                             "): the chessboard poses and the distances disagree; check this camera's distances "
                             "and the board's square size");
    // Every camera faces the seated user; one that faces away was placed through a mirror
    // image, which a left/right swap of the corner names produces.
    const Eigen::Vector3d optical_axis = placed.camera.camera_from_site.linear().transpose() * Eigen::Vector3d::UnitZ();
    if (!(optical_axis.z() > 0.0))
      throw CalibrationError("camera '" + placed.camera.name +
                             "' would look away from the user (its optical axis points behind the screen): are the "
                             "corner distances named as the seated user sees the screen (left = the user's left)?");
  }
  return result;
}

}  // namespace rt::calibration
