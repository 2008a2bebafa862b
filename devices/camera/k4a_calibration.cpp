#include "camera/k4a_calibration.h"

#include <nlohmann/json.hpp>

#include <cmath>

namespace rt::camera::k4a {

namespace {

using nlohmann::json;

constexpr const char* kDepthLocation = "CALIBRATION_CameraLocationD0";
constexpr const char* kColorLocation = "CALIBRATION_CameraLocationPV0";
constexpr const char* kBrownConrady = "CALIBRATION_LensDistortionModelBrownConrady";
constexpr uint32_t kDepthSensorSize = 1024;
constexpr uint32_t kColorSensorWidth = 4096, kColorSensorHeight = 3072, kLegacyColorSensorHeight = 2304;
// Fourteen: cx, cy, fx, fy, k1..k6, codx, cody, p2, p1. Some files add the metric radius.
constexpr size_t kModelParameterCount = 14;

const json& field(const json& object, const char* name, const std::string& where) {
  if (!object.is_object() || !object.contains(name)) throw CalibrationError(where + ": missing field '" + name + "'");
  return object.at(name);
}

double number(const json& value, const std::string& where) {
  if (!value.is_number()) throw CalibrationError(where + " must be a number");
  const double x = value.get<double>();
  if (!std::isfinite(x)) throw CalibrationError(where + " must be finite");
  return x;
}

std::vector<double> numbers(const json& value, size_t min_count, size_t max_count, const std::string& where) {
  if (!value.is_array() || value.size() < min_count || value.size() > max_count)
    throw CalibrationError(where + " must be an array of " + std::to_string(min_count) +
                           (min_count == max_count ? "" : " to " + std::to_string(max_count)) + " numbers");
  std::vector<double> out;
  for (size_t i = 0; i < value.size(); ++i) out.push_back(number(value[i], where + "[" + std::to_string(i) + "]"));
  return out;
}

Eigen::Isometry3d rt_from_json(const json& rt, const std::string& where) {
  const std::vector<double> r = numbers(field(rt, "Rotation", where), 9, 9, where + " Rotation");
  const std::vector<double> t = numbers(field(rt, "Translation", where), 3, 3, where + " Translation");
  Eigen::Matrix3d rotation;
  rotation << r[0], r[1], r[2], r[3], r[4], r[5], r[6], r[7], r[8];
  // The files store single-precision floats: a rotation is orthonormal to about 1e-6 there.
  if ((rotation * rotation.transpose() - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-4 ||
      rotation.determinant() < 0)
    throw CalibrationError(where + " Rotation is not a rotation (row-major 3x3, orthonormal, det +1)");
  Eigen::Isometry3d transform = Eigen::Isometry3d::Identity();
  transform.linear() = rotation;
  transform.translation() = Eigen::Vector3d(t[0], t[1], t[2]);
  return transform;
}

json rt_to_json(const Eigen::Isometry3d& transform) {
  json rotation = json::array();
  for (int row = 0; row < 3; ++row)
    for (int col = 0; col < 3; ++col) rotation.push_back(transform.linear()(row, col));
  const Eigen::Vector3d t = transform.translation();
  return {{"Rotation", rotation}, {"Translation", {t.x(), t.y(), t.z()}}};
}

SensorCalibration sensor_from_json(const json& camera, const std::string& where) {
  SensorCalibration s;
  const json& intrinsics = field(camera, "Intrinsics", where);
  const json& type = field(intrinsics, "ModelType", where + " Intrinsics");
  if (!type.is_string() || type.get<std::string>() != kBrownConrady)
    throw CalibrationError(where + ": Intrinsics ModelType " + type.dump() + " is not supported (only " +
                           kBrownConrady + ", OpenCV's model)");
  const std::vector<double> p = numbers(field(intrinsics, "ModelParameters", where + " Intrinsics"),
                                        kModelParameterCount, kModelParameterCount + 1, where + " ModelParameters");
  s.cx = p[0], s.cy = p[1], s.fx = p[2], s.fy = p[3];
  s.k1 = p[4], s.k2 = p[5], s.k3 = p[6], s.k4 = p[7], s.k5 = p[8], s.k6 = p[9];
  // p[10], p[11]: the centre of distortion, which the Brown-Conrady model does not use.
  s.p2 = p[12], s.p1 = p[13];
  if (!(s.fx > 0 && s.fy > 0)) throw CalibrationError(where + ": ModelParameters fx, fy must be > 0");
  const auto size = [&](const char* name) {
    const double v = number(field(camera, name, where), where + " " + name);
    if (v < 1 || v > 65536 || v != std::floor(v))
      throw CalibrationError(where + ": " + name + " must be a whole number of pixels in [1, 65536]");
    return uint32_t(v);
  };
  s.sensor_width = size("SensorWidth");
  s.sensor_height = size("SensorHeight");
  s.metric_radius = camera.contains("MetricRadius") ? number(camera.at("MetricRadius"), where + " MetricRadius") : 0.0;
  s.camera_from_reference = rt_from_json(field(camera, "Rt", where), where + " Rt");
  return s;
}

json sensor_to_json(const SensorCalibration& s, const char* location, const char* purpose) {
  const json parameters = {s.cx, s.cy, s.fx, s.fy, s.k1, s.k2, s.k3, s.k4, s.k5, s.k6, 0.0, 0.0, s.p2, s.p1};
  return {
      {"Intrinsics",
       {{"ModelParameterCount", kModelParameterCount}, {"ModelParameters", parameters}, {"ModelType", kBrownConrady}}},
      {"Location", location},
      {"Purpose", purpose},
      {"MetricRadius", s.metric_radius},
      {"Rt", rt_to_json(s.camera_from_reference)},
      {"SensorHeight", s.sensor_height},
      {"SensorWidth", s.sensor_width},
      {"Shutter", "CALIBRATION_ShutterTypeUndefined"}};
}

// The SDK's playback parses the IMU entries with the cameras; ours are zeros (no IMU is simulated).
json inertial_sensor(const char* type) {
  const auto zeros = [](size_t n) { return json(std::vector<double>(n, 0.0)); };
  return {{"BiasTemperatureModel", zeros(12)},
          {"BiasUncertainty", zeros(3)},
          {"MixingMatrixTemperatureModel", zeros(36)},
          {"ModelTypeMask", 16},
          {"Noise", zeros(6)},
          {"Rt", rt_to_json(Eigen::Isometry3d::Identity())},
          {"SecondOrderScaling", zeros(9)},
          {"SensorType", type},
          {"TemperatureBounds", zeros(2)},
          {"TemperatureC", 0.0}};
}

void require_sensor(const SensorCalibration& s, uint32_t width, uint32_t height, const char* what) {
  if (s.sensor_width != width || s.sensor_height != height)
    throw CalibrationError(std::string("k4a ") + what + " calibration is for a " + std::to_string(s.sensor_width) +
                           "x" + std::to_string(s.sensor_height) + " sensor, expected " + std::to_string(width) + "x" +
                           std::to_string(height));
}

CameraIntrinsics at_mode(const SensorCalibration& s, const SensorCut& cut) {
  CameraIntrinsics k;
  k.width = cut.output_width;
  k.height = cut.output_height;
  k.fx = s.fx * cut.binned_width;
  k.fy = s.fy * cut.binned_height;
  // Unitized 0-cornered -> pixels -> crop -> (0, 0) at the first pixel's centre.
  k.cx = s.cx * cut.binned_width - cut.crop_x - 0.5;
  k.cy = s.cy * cut.binned_height - cut.crop_y - 0.5;
  k.distortion = {s.k1, s.k2, s.p1, s.p2, s.k3, s.k4, s.k5, s.k6};
  return k;
}

SensorCalibration sensor_for(const CameraIntrinsics& k, const SensorCut& cut, uint32_t width, uint32_t height,
                             const char* what) {
  if (k.width != cut.output_width || k.height != cut.output_height)
    throw CalibrationError(std::string("k4a ") + what + " image is " + std::to_string(k.width) + "x" +
                           std::to_string(k.height) + ", the mode's is " + std::to_string(cut.output_width) + "x" +
                           std::to_string(cut.output_height));
  SensorCalibration s;
  s.sensor_width = width;
  s.sensor_height = height;
  s.fx = k.fx / cut.binned_width;
  s.fy = k.fy / cut.binned_height;
  s.cx = (k.cx + 0.5 + cut.crop_x) / cut.binned_width;
  s.cy = (k.cy + 0.5 + cut.crop_y) / cut.binned_height;
  const Distortion& d = k.distortion;
  s.k1 = d.k1, s.k2 = d.k2, s.k3 = d.k3, s.k4 = d.k4, s.k5 = d.k5, s.k6 = d.k6, s.p1 = d.p1, s.p2 = d.p2;
  return s;
}

}  // namespace

DeviceCalibration parse_calibration_json(std::string_view text, const std::string& where) {
  const json document = json::parse(text, nullptr, false);
  if (document.is_discarded()) throw CalibrationError(where + ": calibration.json is not valid JSON");
  const json& information = field(document, "CalibrationInformation", where);
  const json& cameras = field(information, "Cameras", where + " CalibrationInformation");
  if (!cameras.is_array()) throw CalibrationError(where + ": CalibrationInformation Cameras must be an array");
  const json* depth = nullptr;
  const json* color = nullptr;
  for (const json& camera : cameras) {
    if (!camera.is_object() || !camera.contains("Location") || !camera.at("Location").is_string()) continue;
    const std::string location = camera.at("Location").get<std::string>();
    if (location == kDepthLocation && !depth) depth = &camera;
    if (location == kColorLocation && !color) color = &camera;
  }
  if (!depth) throw CalibrationError(where + ": no camera with Location " + kDepthLocation + " (the depth camera)");
  if (!color) throw CalibrationError(where + ": no camera with Location " + kColorLocation + " (the colour camera)");
  DeviceCalibration calibration;
  calibration.depth = sensor_from_json(*depth, where + " depth camera");
  calibration.color = sensor_from_json(*color, where + " colour camera");
  if (information.contains("Metadata") && information.at("Metadata").is_object() &&
      information.at("Metadata").contains("SerialId") && information.at("Metadata").at("SerialId").is_string())
    calibration.serial = information.at("Metadata").at("SerialId").get<std::string>();
  return calibration;
}

std::string write_calibration_json(const DeviceCalibration& calibration) {
  const json document = {
      {"CalibrationInformation",
       {{"Cameras",
         {sensor_to_json(calibration.depth, kDepthLocation, "CALIBRATION_CameraPurposeDepth"),
          sensor_to_json(calibration.color, kColorLocation, "CALIBRATION_CameraPurposePhotoVideo")}},
        {"InertialSensors",
         {inertial_sensor("CALIBRATION_InertialSensorType_Gyro"),
          inertial_sensor("CALIBRATION_InertialSensorType_Accelerometer")}},
        {"Metadata", {{"SerialId", calibration.serial}, {"Version", {{"Major", 1}, {"Minor", 2}}}}}}}};
  return document.dump();
}

SensorCalibration color_sensor_as_4x3(const SensorCalibration& color) {
  if (uint64_t(color.sensor_width) * 3 == uint64_t(color.sensor_height) * 4) return color;
  if (uint64_t(color.sensor_width) * 9 != uint64_t(color.sensor_height) * 16)
    throw CalibrationError("k4a colour calibration: sensor " + std::to_string(color.sensor_width) + "x" +
                           std::to_string(color.sensor_height) + " is neither 4:3 nor 16:9");
  // The 16:9 image is the middle rows of the 4:3 sensor: as many rows again as an eighth of its
  // height lie above it (384 of 3072 at full size).
  SensorCalibration out = color;
  const double rows_16x9 = color.sensor_height;
  const double rows_4x3 = color.sensor_width * 3.0 / 4.0;
  const double offset = (rows_4x3 - rows_16x9) / 2.0;
  out.cy = (color.cy * rows_16x9 + offset) / rows_4x3;
  out.fy = color.fy * rows_16x9 / rows_4x3;
  out.sensor_height = uint32_t(rows_4x3);
  return out;
}

CameraIntrinsics depth_intrinsics(const SensorCalibration& depth, DepthMode mode) {
  require_sensor(depth, kDepthSensorSize, kDepthSensorSize, "depth");
  return at_mode(depth, sensor_cut(mode));
}

CameraIntrinsics color_intrinsics(const SensorCalibration& color, ColorResolution resolution) {
  if (color.sensor_height != kLegacyColorSensorHeight)
    require_sensor(color, kColorSensorWidth, kColorSensorHeight, "colour");
  if (color.sensor_width != kColorSensorWidth)
    require_sensor(color, kColorSensorWidth, kLegacyColorSensorHeight, "colour");
  return at_mode(color_sensor_as_4x3(color), sensor_cut(resolution));
}

SensorCalibration depth_sensor_for(const CameraIntrinsics& intrinsics, DepthMode mode) {
  return sensor_for(intrinsics, sensor_cut(mode), kDepthSensorSize, kDepthSensorSize, "depth");
}

SensorCalibration color_sensor_for(const CameraIntrinsics& intrinsics, ColorResolution resolution) {
  return sensor_for(intrinsics, sensor_cut(resolution), kColorSensorWidth, kColorSensorHeight, "colour");
}

}  // namespace rt::camera::k4a
