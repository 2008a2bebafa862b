#pragma once
// The cameras' poses in the site frame (the paper's device calibration): relative poses from
// simultaneous chessboard views, chained to the reference camera; each camera's position in
// the site frame trilaterated from its measured distances to the screen corners; and the rigid
// transform (no scale) that best carries the reference-frame positions onto the site-frame
// ones. Needs three or more cameras not on one line.
#include <vector>

#include "calibration/camera_network.h"
#include "calibration/extrinsics_input.h"
#include "calibration/rigid_alignment.h"
#include "calibration/screen_trilateration.h"
#include "geometry/camera.h"

namespace rt::calibration {

// After the alignment a camera this far from where its distances put it means the chessboard
// poses and the tape measure disagree (a wrong square size, a swapped distance), not noise.
constexpr double kMaxAlignmentResidualM = 0.03;

struct ExtrinsicsLimits {
  double max_corner_distance_residual_m = kMaxCornerDistanceResidualM;
  double max_link_rms_px = kMaxLinkRmsPx;
  double max_alignment_residual_m = kMaxAlignmentResidualM;
};

struct PlacedCamera {
  Camera camera;  // intrinsics and camera_from_site
  CameraLink link;
  Trilateration trilateration;
  double alignment_residual_m = 0;  // |trilaterated position - aligned chessboard position|
};

struct ExtrinsicsResult {
  std::vector<PlacedCamera> cameras;  // in the input's order
  double alignment_rms_m = 0;
};

ExtrinsicsResult calibrate_extrinsics(const ExtrinsicsInput& input, const ExtrinsicsLimits& limits = {});

}  // namespace rt::calibration
