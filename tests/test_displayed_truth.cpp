// What the demo measures from the two sites' records (site/displayed_truth.h): the whole frame's
// PSNR and, per touch phase, the hand and forearm's, on a synthetic record with known answers.
#include <catch2/catch.hpp>

#include <unistd.h>

#include <cmath>
#include <fstream>

#include "image/image_io.h"
#include "shared/config.h"
#include "site/displayed_truth.h"
#include "site/site_display.h"

using namespace rt;

namespace {

HostImage gray(uint32_t w, uint32_t h, float value) {
  HostImage image(w, h, PixelFormat::RGBA8, value);
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x) image.at(x, y, 3) = 1.0f;
  return image;
}

// A hand and forearm in rows 3-6, columns 4-9 (hand 4-6, forearm 7-9).
evaluation::HandRegion limb_region(uint32_t w, uint32_t h) {
  evaluation::HandRegion region;
  region.width = w;
  region.height = h;
  region.hand_arm.assign(size_t(w) * h, 0);
  region.hand.assign(size_t(w) * h, 0);
  for (uint32_t y = 3; y <= 6; ++y)
    for (uint32_t x = 4; x <= 9; ++x) {
      region.hand_arm[y * w + x] = 1;
      region.hand[y * w + x] = x <= 6;
    }
  return region;
}

}  // namespace

TEST_CASE("displayed frames against the other site's record: whole-frame PSNR and hand+arm per phase") {
  const auto dir = std::filesystem::temp_directory_path() / ("remotetouch-test-displayed-truth-" + std::to_string(getpid()));
  std::filesystem::remove_all(dir);
  const auto shown = dir / "site_A", captured = dir / "site_B";
  std::filesystem::create_directories(shown / "frames");
  std::filesystem::create_directories(captured / "truth");
  const uint32_t w = 17, h = 11;
  // 8-bit values 102 and 128: every channel of every pixel off by 26/255.
  const float dark = 102.0f / 255.0f, light = 128.0f / 255.0f;
  const double expected_db = 10.0 * std::log10(1.0 / std::pow(26.0 / 255.0, 2));
  write_image(shown / "frames" / site::frame_name(0), gray(w, h, dark));
  write_image(shown / "frames" / site::frame_name(1), gray(w, h, light));
  write_image(shown / "frames" / site::frame_name(2), gray(w, h, light));
  for (uint64_t frame : {3u, 4u, 5u}) write_image(captured / "truth" / site::frame_name(frame), gray(w, h, light));
  {
    site::TruthRegionWriter regions(captured / "truth");
    regions.write(3, limb_region(w, h), 0.005, evaluation::TouchPhase::Touching);
    regions.write(4, limb_region(w, h), 0.5, evaluation::TouchPhase::Far);
    // Frame 5 has no region: the run ended before it was written.
  }
  std::ofstream(captured / "truth" / "hands.jsonl", std::ios::app) << "{not json\n"
                                                                   << R"({"frame": 5, "d_m": 0.3, "phase": "approach"})" << "\n";
  std::ofstream(shown / "frames.jsonl") << R"({"display": 0, "portrait_frame": 3})" << "\n"
                                        << R"({"display": 1, "portrait_frame": 4})" << "\n"
                                        << R"({"display": 9, "portrait_frame": null, "link_lost": true})" << "\n"
                                        << R"({"display": 2, "portrait_frame": 5})" << "\n";

  const nlohmann::json m = site::measure_displayed_frames(shown, captured);
  CHECK(m["frames"] == 3);
  CHECK(m["final_db"].get<double>() == Approx(99.0));  // frame 5: identical
  CHECK(m["mean_db"].get<double>() == Approx((expected_db + 99.0 + 99.0) / 3.0).margin(1e-3));
  REQUIRE(m.contains("hand_arm"));
  const auto& touching = m["hand_arm"]["touching"];
  CHECK(touching["frames"] == 1);
  CHECK(touching["psnr_hand_arm_db"].get<double>() == Approx(expected_db).margin(1e-3));
  CHECK(touching["de_hand"].get<double>() > 1.0);
  CHECK(m["hand_arm"]["far"]["psnr_hand_arm_db"].get<double>() == Approx(99.0));
  CHECK(m["hand_arm"]["far"]["de_hand"].get<double>() == Approx(0.0).margin(1e-9));
  CHECK_FALSE(m["hand_arm"].contains("approach"));  // no region recorded for frame 5
  CHECK_FALSE(touching.contains("iou_hand_arm"));
  CHECK(m.dump().find("NaN") == std::string::npos);

  // Nothing recorded at all: no frames, no hand figures, nulls rather than NaN.
  const nlohmann::json none = site::measure_displayed_frames(dir / "nothing", dir / "nothing");
  CHECK(none["frames"] == 0);
  CHECK(none["final_db"].is_null());
  CHECK_FALSE(none.contains("hand_arm"));
  std::filesystem::remove_all(dir);
}
