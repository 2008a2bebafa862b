// A simulated site written as k4a recordings (what `simulate --format k4a` does) and read back
// through FFmpeg, camera by camera, against the frames the simulator rendered: intrinsics equal
// to the site's cameras, colour-from-depth the identity (the simulator renders both from one
// centre), device times as rendered, depth exactly, colour within the JPEG's error.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>

#include "camera/k4a_recording_reader.h"
#include "camera/k4a_site_writer.h"
#include "pipeline/site_simulator.h"
#include "sim/scene.h"
#include "support/gpu_test.h"
#include "support/output_dir.h"

using namespace rt;
using namespace rt::camera::k4a;

namespace {

const std::filesystem::path kOutK4aSimulatedSite = rt::test::output_dir("test_k4a_simulated_site");
constexpr int kJpegQualityK4aSimulatedSite = 90;
// The simulator's images have hard edges (the user against black), where a JPEG rings: the
// tolerance is on the mean error of a channel and on the share of values off by more than 16/255
// (at quality 90 the worst camera, bottom-centre, measured 0.78/255 and 0.68 %; the others
// 0.34 to 0.51/255 and 0.30 to 0.48 %).
constexpr double kMeanToleranceK4aSimulatedSite = 1.5 / 255, kFarShareTolerance = 0.015;

}  // namespace

TEST_CASE("k4a: a simulated site written as k4a recordings reads back as rendered") {
  test::NoValidationErrors no_validation_errors;
  sim::Scene scene = sim::load_scene(sim::resolve_scene("clap"));
  scene.frame_count = 2;
  scene.resolution_scale = 1.0;  // the default site's cameras are then k4a modes: 720p, WFOV 2x2 binned
  pipeline::SiteSimulator simulator(test::gpu(), scene, Site::A);
  const sim::SiteDescription& site = scene.at(Site::A).site;
  const std::filesystem::path dir = kOutK4aSimulatedSite / "site";
  std::filesystem::remove_all(dir);

  std::vector<sim::RgbdFrame> frames;
  {
    SiteWriter writer(dir, site, uint32_t(scene.fps), kJpegQualityK4aSimulatedSite);
    while (std::optional<sim::RgbdFrame> frame = simulator.next_frame()) {
      writer.write_frame(*frame);
      frames.push_back(std::move(*frame));
    }
    writer.close();
  }
  REQUIRE(frames.size() == 2);

  for (size_t k = 0; k < site.cameras.size(); ++k) {
    const sim::RgbdCamera& camera = site.cameras[k];
    INFO("camera " << camera.name);
    RecordingReader reader(recording_path(dir, camera.name));
    const RecordingInfo& info = reader.info();
    CHECK(info.color_resolution == ColorResolution::p720);
    CHECK(info.depth_mode == DepthMode::wfov_2x2_binned);
    CHECK(info.fps == 30);
    CHECK(info.serial == site.name + "-" + camera.name);
    for (const auto& [read, rendered] : {std::pair{info.color, camera.color}, std::pair{info.depth, camera.depth}}) {
      CHECK(read.width == rendered.width);
      CHECK(read.height == rendered.height);
      CHECK(read.fx == Approx(rendered.fx).margin(1e-9));
      CHECK(read.fy == Approx(rendered.fy).margin(1e-9));
      CHECK(read.cx == Approx(rendered.cx).margin(1e-9));
      CHECK(read.cy == Approx(rendered.cy).margin(1e-9));
      CHECK(read.distortion.as_opencv() == rendered.distortion.as_opencv());
    }
    CHECK(info.color_from_depth().matrix().isApprox(Eigen::Matrix4d::Identity()));

    for (const sim::RgbdFrame& frame : frames) {
      INFO("frame " << frame.index);
      const sim::RgbdImage& rendered = frame.cameras[k];
      const std::optional<Capture> capture = reader.next_capture();
      REQUIRE(capture);
      CHECK(capture->color_device_us == rendered.timestamp_us);
      CHECK(capture->depth_device_us == rendered.timestamp_us);
      REQUIRE(capture->depth_mm.width == rendered.depth_mm.width);
      CHECK(capture->depth_mm.texels == rendered.depth_mm.texels);
      REQUIRE(capture->color.width == rendered.color.width);
      REQUIRE(capture->color.height == rendered.color.height);
      double sum = 0;
      size_t far = 0, values = 0;
      for (uint32_t y = 0; y < rendered.color.height; ++y)
        for (uint32_t x = 0; x < rendered.color.width; ++x)
          for (uint32_t c = 0; c < 3; ++c, ++values) {
            const double error = std::abs(capture->color.at(x, y, c) - rendered.color.at(x, y, c));
            sum += error;
            far += error > 16.0 / 255;
          }
      const double mean = sum / values, far_share = double(far) / values;
      CHECK(mean < kMeanToleranceK4aSimulatedSite);
      CHECK(far_share < kFarShareTolerance);
      if (frame.index == 0)
        std::printf("k4a simulated site, %s frame %llu: colour error mean %.2f/255, %.3f %% off by more than 16/255\n",
                    camera.name.c_str(), static_cast<unsigned long long>(frame.index), mean * 255, far_share * 100);
    }
    CHECK(!reader.next_capture());
  }
}
