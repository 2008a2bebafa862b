// The recording format: what the writer puts down, the replay source gives back exactly.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <random>

#include "image/image_io.h"
#include "sim/recording.h"
#include "support/gpu_test.h"

using namespace rt;

namespace {

std::filesystem::path fresh_dir(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / ("remotetouch-test-recording-" + std::to_string(getpid())) / name;
  std::filesystem::remove_all(dir);
  return dir;
}

nlohmann::json calibration() {
  return {{"name", "test site"}, {"cameras", {{{"name", "left"}}, {{"name", "right"}}}}};
}

sim::RgbdFrame random_frame(std::mt19937& rng, uint64_t index) {
  sim::RgbdFrame frame;
  frame.index = index;
  frame.timestamp_us = 1'000'000 + index * 33'333;
  for (const char* name : {"left", "right"}) {
    sim::RgbdImage image;
    image.camera = name;
    image.timestamp_us = frame.timestamp_us + (name[0] == 'l' ? 120 : 0);
    image.color = test::random_image(rng, 17, 9, PixelFormat::RGBA8);
    for (float& v : image.color.texels) v = std::round(v * 255.0f) / 255.0f;
    image.depth_mm = HostImage(13, 11, PixelFormat::R16U);
    std::uniform_int_distribution<int> millimetres(0, 65535);
    for (float& v : image.depth_mm.texels) v = float(millimetres(rng));
    frame.cameras.push_back(std::move(image));
  }
  return frame;
}

}  // namespace

TEST_CASE("a replayed recording reproduces the written frames exactly", "[recording]") {
  std::mt19937 rng(51);
  const auto dir = fresh_dir("round-trip");
  std::vector<sim::RgbdFrame> written;
  {
    sim::RecordingWriter writer(dir, calibration());
    for (uint64_t i = 0; i < 3; ++i) {
      written.push_back(random_frame(rng, i));
      writer.write_frame(written.back());
    }
  }
  sim::ReplayRgbdSource replay(dir);
  CHECK(replay.frame_count() == 3);
  CHECK(replay.calibration()["format"] == sim::kRecordingFormat);
  for (const auto& expected : written) {
    const auto frame = replay.next_frame();
    REQUIRE(frame);
    CHECK(frame->index == expected.index);
    CHECK(frame->timestamp_us == expected.timestamp_us);
    REQUIRE(frame->cameras.size() == 2);
    for (size_t k = 0; k < 2; ++k) {
      CHECK(frame->cameras[k].camera == expected.cameras[k].camera);
      CHECK(frame->cameras[k].timestamp_us == expected.cameras[k].timestamp_us);
      RT_REQUIRE_MATCHES(frame->cameras[k].color, expected.cameras[k].color, 0.0, 0.0);
      RT_REQUIRE_MATCHES(frame->cameras[k].depth_mm, expected.cameras[k].depth_mm, 0.0, 0.0);
    }
  }
  CHECK_FALSE(replay.next_frame());
}

TEST_CASE("broken recordings say what is wrong", "[recording]") {
  std::mt19937 rng(52);
  const auto dir = fresh_dir("broken");
  {
    sim::RecordingWriter writer(dir, calibration());
    writer.write_frame(random_frame(rng, 0));
    sim::RgbdFrame wrong = random_frame(rng, 1);
    wrong.cameras.pop_back();
    CHECK_THROWS_WITH(writer.write_frame(wrong), Catch::Contains("has 1 cameras"));
  }
  std::ofstream(dir / "frames.jsonl", std::ios::app) << "{not json\n";
  CHECK_THROWS_WITH(sim::ReplayRgbdSource(dir), Catch::Contains("line 2") && Catch::Contains("not valid JSON"));
  CHECK_THROWS_WITH(sim::ReplayRgbdSource(fresh_dir("missing")), Catch::Contains("calibration.json"));
  nlohmann::json no_cameras = {{"name", "x"}};
  CHECK_THROWS_WITH(sim::RecordingWriter(fresh_dir("no-cameras"), no_cameras), Catch::Contains("'cameras'"));
}

TEST_CASE("ground truth masks and depth are written", "[recording]") {
  const auto dir = fresh_dir("ground-truth");
  sim::RecordingWriter writer(dir, calibration());
  HostImage part(5, 4, PixelFormat::R32F, 0.0f), depth(5, 4, PixelFormat::R32F, 0.0f);
  part.at(1, 1) = 2.0f;  // hand
  part.at(2, 2) = 1.0f;  // body
  depth.at(1, 1) = 0.7004f;
  writer.write_ground_truth(0, HostImage(5, 4, PixelFormat::RGBA8, 1.0f), depth, part, {part, part});
  const HostImage hand = read_image(dir / "gt" / "target_hand_mask_000000.png");
  CHECK(hand.at(1, 1) == 1.0f);
  CHECK(hand.at(2, 2) == 0.0f);
  CHECK(read_depth_png(dir / "gt" / "target_depth_000000.png").at(1, 1) == 700.0f);
  CHECK(read_image(dir / "gt" / "cam1" / "foreground_000000.png").at(2, 2) == 1.0f);
}
