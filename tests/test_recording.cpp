// The recording format: what the writer puts down, the replay source gives back exactly.
#include <catch2/catch.hpp>
#include <chrono>

#include <filesystem>
#include <fstream>
#include <random>

#include "image/image_io.h"
#include "sim/default_site.h"
#include "sim/recording.h"
#include "support/gpu_test.h"

using namespace rt;

namespace {

std::filesystem::path fresh_dir(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / ("remotetouch-test-recording-" + std::to_string(getpid())) / name;
  std::filesystem::remove_all(dir);
  return dir;
}

// The default site with two cameras, its intrinsics at the recorded images' (small) sizes.
sim::SiteDescription recorded_site() {
  sim::SiteDescription site = sim::make_default_site();
  site.cameras.resize(2);
  site.cameras[0].name = "left";
  site.cameras[1].name = "right";
  for (sim::RgbdCamera& camera : site.cameras) {
    camera.color = scaled_intrinsics(camera.color, 0.02);
    camera.depth = scaled_intrinsics(camera.depth, 0.03);
  }
  return site;
}

nlohmann::json calibration() { return sim::site_to_json(recorded_site()); }

sim::RgbdFrame random_frame(std::mt19937& rng, uint64_t index) {
  sim::RgbdFrame frame;
  frame.index = index;
  frame.timestamp_us = 1'000'000 + index * 33'333;
  for (const sim::RgbdCamera& camera : recorded_site().cameras) {
    sim::RgbdImage image;
    image.camera = camera.name;
    image.timestamp_us = frame.timestamp_us + (camera.name == "left" ? 120 : 0);
    image.color = test::random_image(rng, camera.color.width, camera.color.height, PixelFormat::RGBA8);
    for (float& v : image.color.texels) v = std::round(v * 255.0f) / 255.0f;
    image.depth_mm = HostImage(camera.depth.width, camera.depth.height, PixelFormat::R16U);
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

TEST_CASE("frames.jsonl: frame numbers and times must be non-negative integers", "[recording]") {
  std::mt19937 rng(53);
  const auto dir = fresh_dir("frame-numbers");
  {
    sim::RecordingWriter writer(dir, calibration());
    writer.write_frame(random_frame(rng, 0));
  }
  const std::string good = [&] {
    std::ifstream in(dir / "frames.jsonl");
    std::string line;
    std::getline(in, line);
    return line;
  }();
  auto with = [&](const std::string& field, const nlohmann::json& value, bool in_camera = false) {
    nlohmann::json line = nlohmann::json::parse(good);
    if (in_camera) line["cameras"][0][field] = value;
    else line[field] = value;
    std::ofstream(dir / "frames.jsonl") << line.dump() << "\n";
  };
  with("frame", 1e300);
  CHECK_THROWS_WITH(sim::ReplayRgbdSource(dir), Catch::Contains("line 1") && Catch::Contains("'frame' must be a non-negative integer, not the number 1e+300"));
  with("frame", 0.7);
  CHECK_THROWS_WITH(sim::ReplayRgbdSource(dir), Catch::Contains("'frame'") && Catch::Contains("0.7"));
  with("frame", -5);
  CHECK_THROWS_WITH(sim::ReplayRgbdSource(dir), Catch::Contains("'frame' must not be negative"));
  with("timestamp_us", "soon");
  CHECK_THROWS_WITH(sim::ReplayRgbdSource(dir), Catch::Contains("'timestamp_us'") && Catch::Contains("string"));
  with("timestamp_us", -1, true);
  CHECK_THROWS_WITH(sim::ReplayRgbdSource(dir), Catch::Contains("cameras[0]") && Catch::Contains("'timestamp_us' must not be negative"));
  std::ofstream(dir / "frames.jsonl") << "[1, 2]\n";
  CHECK_THROWS_WITH(sim::ReplayRgbdSource(dir), Catch::Contains("line 1") && Catch::Contains("must be a JSON object"));
  with("frame", 0);
  CHECK_NOTHROW(sim::ReplayRgbdSource(dir));
}

TEST_CASE("recorded images: the PNG header is checked before anything is decoded", "[recording]") {
  std::mt19937 rng(54);
  const auto dir = fresh_dir("png-headers");
  {
    sim::RecordingWriter writer(dir, calibration());
    writer.write_frame(random_frame(rng, 0));
  }
  const std::filesystem::path color = sim::color_path(dir, 0, 0), depth = sim::depth_path(dir, 0, 0);
  const std::string good_color = [&] {
    std::ifstream in(color, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  }();
  CHECK(sim::ReplayRgbdSource(dir).next_frame());

  // A decompression bomb: a tiny file whose IHDR declares 10000x10000 (the rest is garbage).
  std::string bomb = good_color.substr(0, 33);
  for (int i = 16; i < 24; i += 4) {
    bomb[size_t(i)] = 0, bomb[size_t(i) + 1] = 0, bomb[size_t(i) + 2] = char(0x27), bomb[size_t(i) + 3] = char(0x10);
  }
  bomb += std::string(300, 'x');
  std::ofstream(color, std::ios::binary) << bomb;
  const auto start = std::chrono::steady_clock::now();
  CHECK_THROWS_WITH(sim::ReplayRgbdSource(dir).next_frame(),
                    Catch::Contains(color.string()) && Catch::Contains("is 10000x10000") && Catch::Contains("not decoded"));
  CHECK(std::chrono::steady_clock::now() - start < std::chrono::seconds(1));

  // Another format under a .png name never reaches OpenCV's other decoders.
  std::ofstream(color, std::ios::binary) << "P6\n3 2\n255\n" << std::string(18, '\x7f');
  CHECK_THROWS_WITH(sim::ReplayRgbdSource(dir).next_frame(), Catch::Contains("is not a PNG"));
  std::ofstream(color, std::ios::binary) << "\x89PNG";
  CHECK_THROWS_WITH(sim::ReplayRgbdSource(dir).next_frame(), Catch::Contains("too short to be a PNG"));

  // The right size, the wrong kind: 16-bit gray where color belongs, and 8-bit color for depth.
  const sim::RgbdCamera left = recorded_site().cameras[0];
  write_image(color, HostImage(left.color.width, left.color.height, PixelFormat::R32F, 0.25f), PngDepth::Sixteen);
  CHECK_THROWS_WITH(sim::ReplayRgbdSource(dir).next_frame(), Catch::Contains("is not an 8-bit RGB or RGBA PNG"));
  std::ofstream(color, std::ios::binary) << good_color;
  write_image(depth, HostImage(left.depth.width, left.depth.height, PixelFormat::RGBA32F, 0.5f));
  CHECK_THROWS_WITH(sim::ReplayRgbdSource(dir).next_frame(), Catch::Contains(depth.string()) &&
                                                                   Catch::Contains("is not a 16-bit one-channel PNG"));
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
