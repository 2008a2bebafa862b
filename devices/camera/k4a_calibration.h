#pragma once
// The factory calibration of a k4a camera (Azure Kinect, Orbbec Femto) as its `calibration.json`
// stores it, and its intrinsics at a recorded mode in our camera model (OpenCV's convention,
// geometry/camera.h).
//
// The file describes the full sensor (depth 1024x1024, colour 4096x3072 or a legacy 4096x2304),
// unitized (principal point and focal lengths divided by the sensor's width and height) and
// 0-cornered ((0, 0) is the top-left corner of the top-left pixel). Its ModelParameters are
// cx, cy, fx, fy, k1..k6, codx, cody, p2, p1: the tangential terms in the reverse of OpenCV's
// order. Each camera's Rt maps the device's reference frame (the depth camera) into it,
// translation in metres.
#include <Eigen/Geometry>

#include <stdexcept>
#include <string>
#include <string_view>

#include "camera/k4a_modes.h"
#include "geometry/camera.h"

namespace rt::camera::k4a {

class CalibrationError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// One camera of the file, unitized and 0-cornered, for its full sensor.
struct SensorCalibration {
  uint32_t sensor_width = 0, sensor_height = 0;
  double cx = 0, cy = 0, fx = 0, fy = 0;
  double k1 = 0, k2 = 0, k3 = 0, k4 = 0, k5 = 0, k6 = 0, p1 = 0, p2 = 0;
  double metric_radius = 0;  // the radius (normalised image plane) where the model is valid
  Eigen::Isometry3d camera_from_reference = Eigen::Isometry3d::Identity();
};

struct DeviceCalibration {
  SensorCalibration depth, color;
  std::string serial;  // Metadata.SerialId; empty when absent
  Eigen::Isometry3d color_from_depth() const {
    return color.camera_from_reference * depth.camera_from_reference.inverse();
  }
};

// Parses the SDK's schema; errors start with `where` and name the camera and the field. Only
// the Brown-Conrady model (the one the devices are calibrated with) is accepted: it is OpenCV's.
DeviceCalibration parse_calibration_json(std::string_view text, const std::string& where);
// The same schema, IMU entries included (zeros: we have no IMU), so that the SDK's own playback
// accepts the file.
std::string write_calibration_json(const DeviceCalibration& calibration);

// A legacy 16:9 colour calibration (4096x2304) as the 4:3 sensor it was cut from; a 4:3 one
// unchanged. Throws CalibrationError for any other aspect.
SensorCalibration color_sensor_as_4x3(const SensorCalibration& color);

// The intrinsics of the images at a mode: scaled to the mode's binned size, shifted by its
// crop, and moved to pixel centres (OpenCV's convention). Throws CalibrationError when the
// sensor is not the one the mode is cut from.
CameraIntrinsics depth_intrinsics(const SensorCalibration& depth, DepthMode mode);
CameraIntrinsics color_intrinsics(const SensorCalibration& color, ColorResolution resolution);

// The full-sensor calibration whose mode-specific intrinsics are `intrinsics` (the inverse of
// the two above): how a simulated camera is written into a recording. Throws CalibrationError
// when the size is not the mode's.
SensorCalibration depth_sensor_for(const CameraIntrinsics& intrinsics, DepthMode mode);
SensorCalibration color_sensor_for(const CameraIntrinsics& intrinsics, ColorResolution resolution);

}  // namespace rt::camera::k4a
