// The k4a factory calibration (devices/camera/k4a_calibration.h): the SDK's calibration.json
// read and written, and the intrinsics at every depth mode and colour resolution against the
// SDK's mode-specific calibration, worked out here from the mode table of the SDK's sources
// (binned size, crop, output size) rather than from the module's own table.
#include <catch2/catch.hpp>

#include <opencv2/calib3d.hpp>

#include <nlohmann/json.hpp>

#include "camera/k4a_calibration.h"
#include "camera/k4a_modes.h"

using namespace rt;
using namespace rt::camera::k4a;
using Catch::Matchers::Contains;
using nlohmann::json;

namespace {

// Unitized, 0-cornered, full-sensor parameters of a plausible device; p1 and p2 differ in sign
// and size so that reading them in OpenCV's order instead of the file's moves every pixel.
constexpr double kP1 = 4.0e-4, kP2 = -1.5e-3;
const std::vector<double> kDepthParameters = {0.5041, 0.5072, 0.4927, 0.4928, 3.21, 2.05, 0.098,
                                              3.55,   3.05,   0.51,   0.0,    0.0,  kP2,  kP1};
const std::vector<double> kColorParameters = {0.4993, 0.5067, 0.4782, 0.6375, 0.62, -2.83, 1.61,
                                              0.49,   -2.65,  1.54,   0.0,    0.0,  kP2,   kP1};

json camera_json(const char* location, const std::vector<double>& parameters, int width, int height,
                 std::vector<double> rotation, std::vector<double> translation) {
  return {{"Intrinsics",
           {{"ModelParameterCount", 14},
            {"ModelParameters", parameters},
            {"ModelType", "CALIBRATION_LensDistortionModelBrownConrady"}}},
          {"Location", location},
          {"MetricRadius", 1.7},
          {"Rt", {{"Rotation", rotation}, {"Translation", translation}}},
          {"SensorHeight", height},
          {"SensorWidth", width}};
}

// A small rotation about x (the real devices' colour camera is tilted 6 degrees) and a 32 mm
// baseline.
const std::vector<double> kColorRotation = {
    1, 0, 0, 0, 0.9945218953682733, -0.10452846326765347, 0, 0.10452846326765347, 0.9945218953682733};
const std::vector<double> kColorTranslation = {-0.032, -0.002, 0.004};

std::string device_json(int color_height = 3072) {
  const std::vector<double> identity = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  return json{{"CalibrationInformation",
               {{"Cameras",
                 {camera_json("CALIBRATION_CameraLocationD0", kDepthParameters, 1024, 1024, identity, {0, 0, 0}),
                  camera_json("CALIBRATION_CameraLocationPV0", kColorParameters, 4096, color_height, kColorRotation,
                              kColorTranslation)}},
                {"Metadata", {{"SerialId", "000123456789"}}}}}}
      .dump();
}

struct SdkMode {
  int binned_w, binned_h, crop_x, crop_y, out_w, out_h;
};
// The SDK's transformation_get_mode_specific_*_camera_calibration tables.
const std::vector<std::pair<DepthMode, SdkMode>> kSdkDepth = {
    {DepthMode::nfov_2x2_binned, {512, 512, 96, 90, 320, 288}},
    {DepthMode::nfov_unbinned, {1024, 1024, 192, 180, 640, 576}},
    {DepthMode::wfov_2x2_binned, {512, 512, 0, 0, 512, 512}},
    {DepthMode::wfov_unbinned, {1024, 1024, 0, 0, 1024, 1024}}};
const std::vector<std::pair<ColorResolution, SdkMode>> kSdkColor = {
    {ColorResolution::p720, {1280, 960, 0, 120, 1280, 720}},
    {ColorResolution::p1080, {1920, 1440, 0, 180, 1920, 1080}},
    {ColorResolution::p1440, {2560, 1920, 0, 240, 2560, 1440}},
    {ColorResolution::p1536, {2048, 1536, 0, 0, 2048, 1536}},
    {ColorResolution::p2160, {3840, 2880, 0, 360, 3840, 2160}},
    {ColorResolution::p3072, {4096, 3072, 0, 0, 4096, 3072}}};

// What the SDK computes: pixelized, 0-centred fx, fy, cx, cy.
std::array<double, 4> sdk_mode_intrinsics(const std::vector<double>& p, const SdkMode& m) {
  return {p[2] * m.binned_w, p[3] * m.binned_h, p[0] * m.binned_w - m.crop_x - 0.5, p[1] * m.binned_h - m.crop_y - 0.5};
}

// The SDK's Brown-Conrady projection (intrinsic_transformation.c), in its own parameter names.
Eigen::Vector2d sdk_project(const std::vector<double>& p, const std::array<double, 4>& f,
                            const Eigen::Vector3d& point) {
  const double k1 = p[4], k2 = p[5], k3 = p[6], k4 = p[7], k5 = p[8], k6 = p[9], p2 = p[12], p1 = p[13];
  const double xp = point.x() / point.z(), yp = point.y() / point.z();
  const double rs = xp * xp + yp * yp, xyp = xp * yp;
  const double d = (1 + rs * (k1 + rs * (k2 + rs * k3))) / (1 + rs * (k4 + rs * (k5 + rs * k6)));
  const double xd = xp * d + (rs + 2 * xp * xp) * p2 + 2 * xyp * p1;
  const double yd = yp * d + (rs + 2 * yp * yp) * p1 + 2 * xyp * p2;
  return {xd * f[0] + f[2], yd * f[1] + f[3]};
}

const std::vector<Eigen::Vector3d> kPoints = {
    {0.0, 0.0, 1.0}, {0.31, -0.22, 1.4}, {-0.4, 0.27, 0.9}, {0.12, 0.35, 2.1}, {-0.2, -0.3, 0.7}};

// Our intrinsics at a mode against the SDK's, computed from its own table.
template <typename Expected>
void check_same_intrinsics(const CameraIntrinsics& k, const Expected& expected, const SdkMode& sdk) {
  CHECK(k.width == uint32_t(sdk.out_w));
  CHECK(k.height == uint32_t(sdk.out_h));
  CHECK(k.fx == Approx(expected[0]).epsilon(1e-12));
  CHECK(k.fy == Approx(expected[1]).epsilon(1e-12));
  CHECK(k.cx == Approx(expected[2]).epsilon(1e-12));
  CHECK(k.cy == Approx(expected[3]).epsilon(1e-12));
}

}  // namespace

TEST_CASE("k4a: every depth mode's intrinsics are the SDK's mode-specific calibration") {
  const DeviceCalibration calibration = parse_calibration_json(device_json(), "test");
  for (const auto& [mode, sdk] : kSdkDepth) {
    INFO(depth_mode_name(mode));
    const CameraIntrinsics k = depth_intrinsics(calibration.depth, mode);
    const auto expected = sdk_mode_intrinsics(kDepthParameters, sdk);
    check_same_intrinsics(k, expected, sdk);
    CHECK(depth_mode_for_size(k.width, k.height) == mode);
  }
}

TEST_CASE("k4a: every colour resolution's intrinsics are the SDK's mode-specific calibration") {
  const DeviceCalibration calibration = parse_calibration_json(device_json(), "test");
  for (const auto& [resolution, sdk] : kSdkColor) {
    INFO(sdk.out_h << "p");
    const CameraIntrinsics k = color_intrinsics(calibration.color, resolution);
    const auto expected = sdk_mode_intrinsics(kColorParameters, sdk);
    check_same_intrinsics(k, expected, sdk);
    CHECK(color_resolution_for_size(k.width, k.height) == resolution);
  }
}

TEST_CASE("k4a: projection at a mode matches the SDK's model and cv::projectPoints, p1 and p2 in their places") {
  const DeviceCalibration calibration = parse_calibration_json(device_json(), "test");
  const auto check_mode = [](const CameraIntrinsics& k, const std::vector<double>& p, const SdkMode& sdk) {
    const auto f = sdk_mode_intrinsics(p, sdk);
    // OpenCV's order, k1, k2, p1, p2, k3, k4, k5, k6, written out from the file's order here.
    const std::vector<double> opencv = {p[4], p[5], p[13], p[12], p[6], p[7], p[8], p[9]};
    const cv::Matx33d camera_matrix(f[0], 0, f[2], 0, f[1], f[3], 0, 0, 1);
    Camera camera;
    camera.intrinsics = k;
    for (const Eigen::Vector3d& point : kPoints) {
      std::vector<cv::Point2d> reference;
      cv::projectPoints(std::vector<cv::Point3d>{{point.x(), point.y(), point.z()}}, cv::Vec3d(0, 0, 0),
                        cv::Vec3d(0, 0, 0), camera_matrix, opencv, reference);
      const std::optional<Eigen::Vector2d> ours = camera.project(point);
      REQUIRE(ours);
      const Eigen::Vector2d sdk_pixel = sdk_project(p, f, point);
      CHECK(ours->x() == Approx(reference[0].x).margin(1e-6));
      CHECK(ours->y() == Approx(reference[0].y).margin(1e-6));
      CHECK(ours->x() == Approx(sdk_pixel.x()).margin(1e-6));
      CHECK(ours->y() == Approx(sdk_pixel.y()).margin(1e-6));
    }
  };
  check_mode(depth_intrinsics(calibration.depth, DepthMode::nfov_unbinned), kDepthParameters, kSdkDepth[1].second);
  check_mode(color_intrinsics(calibration.color, ColorResolution::p720), kColorParameters, kSdkColor[0].second);

  // The check can fail: the same pixels with the tangential terms swapped are more than a
  // pixel away somewhere.
  CameraIntrinsics swapped = depth_intrinsics(calibration.depth, DepthMode::nfov_unbinned);
  std::swap(swapped.distortion.p1, swapped.distortion.p2);
  Camera right, wrong;
  right.intrinsics = depth_intrinsics(calibration.depth, DepthMode::nfov_unbinned);
  wrong.intrinsics = swapped;
  double largest = 0;
  for (const Eigen::Vector3d& point : kPoints)
    largest = std::max(largest, (*right.project(point) - *wrong.project(point)).norm());
  CHECK(largest > 1.0);
}

TEST_CASE("k4a: colour-from-depth is the colour camera's Rt, in metres") {
  const DeviceCalibration calibration = parse_calibration_json(device_json(), "test");
  const Eigen::Isometry3d color_from_depth = calibration.color_from_depth();
  CHECK(color_from_depth.translation().isApprox(Eigen::Vector3d(-0.032, -0.002, 0.004)));
  CHECK(color_from_depth.linear()(1, 2) == Approx(-0.10452846326765347));
  CHECK(calibration.serial == "000123456789");
}

TEST_CASE("k4a: a legacy 16:9 colour calibration gives the intrinsics of the 4:3 one it was cut from") {
  // The same lens described on the 4096x2304 middle of the 4096x3072 sensor.
  std::vector<double> legacy = kColorParameters;
  legacy[1] = (kColorParameters[1] * 3072 - 384) / 2304;
  legacy[3] = kColorParameters[3] * 3072 / 2304;
  json document = json::parse(device_json(2304));
  document["CalibrationInformation"]["Cameras"][1]["Intrinsics"]["ModelParameters"] = legacy;
  const DeviceCalibration old = parse_calibration_json(document.dump(), "legacy");
  const DeviceCalibration modern = parse_calibration_json(device_json(), "4:3");
  for (const auto& [resolution, sdk] : kSdkColor) {
    const CameraIntrinsics a = color_intrinsics(old.color, resolution);
    const CameraIntrinsics b = color_intrinsics(modern.color, resolution);
    CHECK(a.fy == Approx(b.fy).epsilon(1e-12));
    CHECK(a.cy == Approx(b.cy).epsilon(1e-12));
    CHECK(a.cx == Approx(b.cx).epsilon(1e-12));
  }
}

TEST_CASE("k4a: calibration.json written and read back, and a simulated camera through it") {
  CameraIntrinsics color;
  color.width = 1280, color.height = 720, color.fx = color.fy = 640.0, color.cx = 639.5, color.cy = 359.5;
  color.distortion.p1 = kP1, color.distortion.p2 = kP2, color.distortion.k1 = 0.1;
  CameraIntrinsics depth;
  depth.width = depth.height = 512, depth.fx = depth.fy = 147.8, depth.cx = depth.cy = 255.5;
  DeviceCalibration calibration;
  calibration.depth = depth_sensor_for(depth, DepthMode::wfov_2x2_binned);
  calibration.color = color_sensor_for(color, ColorResolution::p720);
  calibration.color.camera_from_reference.translation() = Eigen::Vector3d(-0.032, 0, 0);
  calibration.serial = "sim-top-left";
  const DeviceCalibration back = parse_calibration_json(write_calibration_json(calibration), "written");
  CHECK(back.serial == "sim-top-left");
  CHECK(back.color.sensor_width == 4096);
  CHECK(back.color.sensor_height == 3072);
  CHECK(back.color_from_depth().translation().isApprox(Eigen::Vector3d(-0.032, 0, 0)));
  const CameraIntrinsics c = color_intrinsics(back.color, ColorResolution::p720);
  const CameraIntrinsics d = depth_intrinsics(back.depth, DepthMode::wfov_2x2_binned);
  CHECK(c.cx == Approx(639.5).epsilon(1e-12));
  CHECK(c.cy == Approx(359.5).epsilon(1e-12));
  CHECK(c.fx == Approx(640.0).epsilon(1e-12));
  CHECK(c.distortion.p1 == kP1);
  CHECK(c.distortion.p2 == kP2);
  CHECK(d.fx == Approx(147.8).epsilon(1e-12));
  CHECK(d.cx == Approx(255.5).epsilon(1e-12));
  // The written parameters are in the file's order: p2 before p1.
  const json written = json::parse(write_calibration_json(calibration));
  const json& parameters = written["CalibrationInformation"]["Cameras"][1]["Intrinsics"]["ModelParameters"];
  CHECK(parameters[12].get<double>() == kP2);
  CHECK(parameters[13].get<double>() == kP1);
  CHECK_THROWS_WITH(color_sensor_for(depth, ColorResolution::p720), Contains("512x512, the mode's is 1280x720"));
}

TEST_CASE("k4a: a bad calibration.json is refused naming what is wrong") {
  CHECK_THROWS_WITH(parse_calibration_json("{", "f.mkv"), Contains("not valid JSON"));
  CHECK_THROWS_WITH(parse_calibration_json("{}", "f.mkv"), Contains("missing field 'CalibrationInformation'"));
  json document = json::parse(device_json());
  document["CalibrationInformation"]["Cameras"].erase(1);
  CHECK_THROWS_WITH(parse_calibration_json(document.dump(), "f.mkv"), Contains("CALIBRATION_CameraLocationPV0"));
  document = json::parse(device_json());
  document["CalibrationInformation"]["Cameras"][0]["Intrinsics"]["ModelParameters"] = {0.5, 0.5};
  CHECK_THROWS_WITH(parse_calibration_json(document.dump(), "f.mkv"), Contains("depth camera ModelParameters"));
  document = json::parse(device_json());
  document["CalibrationInformation"]["Cameras"][0]["Intrinsics"]["ModelType"] = "CALIBRATION_LensDistortionModelTheta";
  CHECK_THROWS_WITH(parse_calibration_json(document.dump(), "f.mkv"), Contains("is not supported"));
  document = json::parse(device_json());
  document["CalibrationInformation"]["Cameras"][1]["Rt"]["Rotation"] = {1, 0, 0, 0, 1, 0, 0, 0, 2};
  CHECK_THROWS_WITH(parse_calibration_json(document.dump(), "f.mkv"), Contains("is not a rotation"));
  document = json::parse(device_json());
  document["CalibrationInformation"]["Cameras"][0]["SensorWidth"] = 640;
  const DeviceCalibration odd = parse_calibration_json(document.dump(), "f.mkv");
  CHECK_THROWS_WITH(depth_intrinsics(odd.depth, DepthMode::nfov_unbinned),
                    Contains("640x1024 sensor, expected 1024x1024"));
  document["CalibrationInformation"]["Cameras"][1]["SensorHeight"] = 3000;
  const DeviceCalibration odder = parse_calibration_json(document.dump(), "f.mkv");
  CHECK_THROWS_WITH(color_intrinsics(odder.color, ColorResolution::p720), Contains("4096x3000 sensor"));
}

TEST_CASE("k4a: mode names, tags and frame rates") {
  CHECK(depth_mode_from_name("NFOV_UNBINNED") == DepthMode::nfov_unbinned);
  CHECK(!depth_mode_from_name("PASSIVE_IR"));
  CHECK(color_mode_tag(ColorFormat::mjpg, ColorResolution::p720) == "MJPG_720P");
  const auto mode = color_mode_from_tag("BGRA_1536P");
  REQUIRE(mode);
  CHECK(mode->format == ColorFormat::bgra);
  CHECK(mode->resolution == ColorResolution::p1536);
  CHECK(!color_mode_from_tag("MJPG_721P"));
  CHECK(color_format_from_fourcc(0x47504A4D) == ColorFormat::mjpg);
  CHECK(frame_period_ns(30) == 33333333);
  CHECK(frame_rate_for_period(33333333) == 30u);
  CHECK(frame_rate_for_period(66666666) == 15u);
  CHECK(frame_rate_for_period(66666667) == 15u);  // 1e9 / 15 rounded up, as libavformat gives it
  CHECK(frame_rate_for_period(200000000) == 5u);
  CHECK(frame_rate_for_period(40000000) == std::nullopt);  // 25 fps
  CHECK(frame_rate_for_period(0) == std::nullopt);
}
