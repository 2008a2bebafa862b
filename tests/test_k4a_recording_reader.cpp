// k4a recordings read back through FFmpeg (devices/camera/k4a_recording_reader.h,
// k4a_inspection.h): every colour format the devices record, depth exactly, times, tags and
// intrinsics as written; and files that are bad in the ways real ones get bad (truncated, no
// calibration, an unknown mode, no frames, a corrupt JPEG), each refused naming the file and what
// is wrong.
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>

#include "camera/k4a_inspection.h"
#include "camera/k4a_recording_reader.h"
#include "camera/k4a_recording_writer.h"
#include "config/json.h"
#include "image/image_io.h"
#include "support/output_dir.h"

using namespace rt;
using namespace rt::camera::k4a;
using Catch::Matchers::Contains;

namespace {

const std::filesystem::path kOut = rt::test::output_dir("test_k4a_recording_reader");
constexpr uint64_t kStartUs = 7'000'000;
constexpr int64_t kDepthDelayNs = 200'000;  // depth 200 us after colour
constexpr uint32_t kPeriodUs = 33'333;
// JPEG at quality 90 on these smooth images: the mean error of a channel stays under 1/255 and no
// pixel is off by more than 8/255 (measured 0.88 and 5); NV12 and YUY2 lose chroma resolution and
// round twice (measured 0.39 and 3, 0.35 and 2). BGRA is exact.
constexpr int kJpegQuality = 90;
constexpr double kMeanTolerance = 1.0 / 255, kMaxTolerance = 8.0 / 255;

HostImage test_color(uint32_t width, uint32_t height, uint32_t index) {
  HostImage image(width, height, PixelFormat::RGBA8);
  for (uint32_t y = 0; y < height; ++y)
    for (uint32_t x = 0; x < width; ++x) {
      image.at(x, y, 0) = std::round(255.0f * (0.5f + 0.4f * std::sin(x * 0.01f + index))) / 255.0f;
      image.at(x, y, 1) = std::round(255.0f * (0.5f + 0.4f * std::cos(y * 0.013f))) / 255.0f;
      image.at(x, y, 2) = std::round(255.0f * (0.3f + 0.2f * std::sin((x + y) * 0.007f))) / 255.0f;
      image.at(x, y, 3) = 1.0f;
    }
  return image;
}

HostImage test_depth(uint32_t width, uint32_t height, uint32_t index) {
  HostImage depth(width, height, PixelFormat::R16U);
  for (uint32_t y = 0; y < height; ++y)
    for (uint32_t x = 0; x < width; ++x)
      depth.at(x, y) = (x + y + index) % 17 == 0 ? 0.0f : float((x * 37 + y * 101 + index * 1000) % 65536);
  return depth;
}

// NV12 and YUY2 as the colour camera gives them: BT.601, limited range.
std::vector<uint8_t> encode_yuv(const HostImage& rgba, ColorFormat format) {
  const uint32_t w = rgba.width, h = rgba.height;
  std::vector<double> Y(size_t(w) * h), U(Y.size()), V(Y.size());
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x) {
      const double r = rgba.at(x, y, 0), g = rgba.at(x, y, 1), b = rgba.at(x, y, 2);
      const size_t i = size_t(y) * w + x;
      Y[i] = 16 + 219 * (0.299 * r + 0.587 * g + 0.114 * b);
      U[i] = 128 + 224 * (-0.168736 * r - 0.331264 * g + 0.5 * b);
      V[i] = 128 + 224 * (0.5 * r - 0.418688 * g - 0.081312 * b);
    }
  const auto byte = [](double v) { return uint8_t(std::clamp(std::lround(v), 0L, 255L)); };
  std::vector<uint8_t> out;
  if (format == ColorFormat::nv12) {
    for (double v : Y) out.push_back(byte(v));
    for (uint32_t y = 0; y < h; y += 2)
      for (uint32_t x = 0; x < w; x += 2) {
        const size_t i = size_t(y) * w + x;
        out.push_back(byte((U[i] + U[i + 1] + U[i + w] + U[i + w + 1]) / 4));
        out.push_back(byte((V[i] + V[i + 1] + V[i + w] + V[i + w + 1]) / 4));
      }
  } else {
    for (size_t i = 0; i < Y.size(); i += 2) {
      out.push_back(byte(Y[i]));
      out.push_back(byte((U[i] + U[i + 1]) / 2));
      out.push_back(byte(Y[i + 1]));
      out.push_back(byte((V[i] + V[i + 1]) / 2));
    }
  }
  return out;
}

std::vector<uint8_t> encode(const HostImage& rgba, ColorFormat format) {
  switch (format) {
    case ColorFormat::mjpg:
      return encode_mjpg(rgba, kJpegQuality);
    case ColorFormat::bgra:
      return encode_bgra(rgba);
    default:
      return encode_yuv(rgba, format);
  }
}

RecordingConfig test_config(ColorFormat format) {
  RecordingConfig config;
  config.color_format = format;
  config.color_resolution = ColorResolution::p720;
  config.depth_mode = DepthMode::nfov_2x2_binned;
  config.fps = 30;
  config.depth_delay_ns = kDepthDelayNs;
  config.wired_sync = WiredSyncMode::master;
  config.serial = "000442922212";
  CameraIntrinsics color;
  color.width = 1280, color.height = 720, color.fx = 611.3, color.fy = 610.9, color.cx = 638.2, color.cy = 366.4;
  color.distortion = {0.52, -2.61, 4.0e-4, -1.5e-3, 1.53, 0.40, -2.45, 1.46};
  CameraIntrinsics depth;
  depth.width = 320, depth.height = 288, depth.fx = 252.4, depth.fy = 252.5, depth.cx = 160.7, depth.cy = 166.1;
  depth.distortion = {3.2, 2.1, -1.0e-4, 6.0e-5, 0.1, 3.5, 3.1, 0.5};
  config.calibration.color = color_sensor_for(color, ColorResolution::p720);
  config.calibration.depth = depth_sensor_for(depth, DepthMode::nfov_2x2_binned);
  config.calibration.color.camera_from_reference.translation() = Eigen::Vector3d(-0.032, -0.002, 0.004);
  return config;
}

// Writes `count` captures; the bytes of capture `corrupt` (if any) are replaced by `bad_color`.
std::filesystem::path write_recording(const std::string& name, ColorFormat format, uint32_t count,
                                      std::optional<uint32_t> corrupt = std::nullopt,
                                      std::vector<uint8_t> bad_color = {}) {
  std::filesystem::create_directories(kOut);
  const std::filesystem::path file = kOut / (name + ".mkv");
  RecordingWriter writer(file, test_config(format));
  for (uint32_t i = 0; i < count; ++i) {
    const std::vector<uint8_t> color = corrupt == i ? bad_color : encode(test_color(1280, 720, i), format);
    writer.write_capture(kStartUs + i * kPeriodUs, color, test_depth(320, 288, i));
  }
  writer.close();
  return file;
}

std::vector<char> read_bytes(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

std::filesystem::path write_bytes(const std::string& name, const std::vector<char>& bytes) {
  const std::filesystem::path file = kOut / name;
  std::ofstream(file, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size()));
  return file;
}

// A copy of `file` with the first occurrence of `from` replaced by `to` (same length).
std::filesystem::path patched(const std::filesystem::path& file, const std::string& name, const std::string& from,
                              const std::string& to) {
  REQUIRE(from.size() == to.size());
  std::vector<char> bytes = read_bytes(file);
  const auto at = std::search(bytes.begin(), bytes.end(), from.begin(), from.end());
  REQUIRE(at != bytes.end());
  std::copy(to.begin(), to.end(), at);
  return write_bytes(name, bytes);
}

}  // namespace

TEST_CASE("k4a reader: every colour format, depth exactly, times, tags and intrinsics as written") {
  for (ColorFormat format : {ColorFormat::mjpg, ColorFormat::nv12, ColorFormat::yuy2, ColorFormat::bgra}) {
    const std::string name(color_format_name(format));
    INFO(name);
    const std::filesystem::path file = write_recording("round_trip_" + name, format, 3);
    RecordingReader reader(file);
    const RecordingInfo& info = reader.info();
    CHECK(info.color_format == format);
    CHECK(info.color_resolution == ColorResolution::p720);
    CHECK(info.depth_mode == DepthMode::nfov_2x2_binned);
    CHECK(info.fps == 30);
    CHECK(info.depth_delay_ns == kDepthDelayNs);
    CHECK(info.wired_sync == WiredSyncMode::master);
    CHECK(info.serial == "000442922212");
    CHECK(info.start_offset_us == kStartUs);
    const RecordingConfig written = test_config(format);
    const CameraIntrinsics color = color_intrinsics(written.calibration.color, ColorResolution::p720);
    CHECK(info.color.fx == Approx(611.3).epsilon(1e-12));
    CHECK(info.color.cy == Approx(366.4).epsilon(1e-12));
    CHECK(info.color.distortion.p1 == color.distortion.p1);
    CHECK(info.color.distortion.p2 == color.distortion.p2);
    CHECK(info.depth.cx == Approx(160.7).epsilon(1e-12));
    CHECK(info.depth.distortion.k4 == 3.5);
    CHECK(info.color_from_depth().translation().isApprox(Eigen::Vector3d(-0.032, -0.002, 0.004)));

    for (uint32_t i = 0; i < 3; ++i) {
      INFO("capture " << i);
      const std::optional<Capture> capture = reader.next_capture();
      REQUIRE(capture);
      CHECK(capture->color_device_us == kStartUs + i * kPeriodUs);
      CHECK(capture->depth_device_us == kStartUs + i * kPeriodUs + kDepthDelayNs / 1000);
      CHECK(capture->depth_mm.texels == test_depth(320, 288, i).texels);
      const HostImage expected = test_color(1280, 720, i);
      REQUIRE(capture->color.width == 1280);
      REQUIRE(capture->color.height == 720);
      double sum = 0, largest = 0;
      for (uint32_t y = 0; y < 720; ++y)
        for (uint32_t x = 0; x < 1280; ++x)
          for (uint32_t c = 0; c < 3; ++c) {
            const double error = std::abs(capture->color.at(x, y, c) - expected.at(x, y, c));
            sum += error;
            largest = std::max(largest, error);
          }
      const double mean = sum / (1280.0 * 720 * 3);
      if (format == ColorFormat::bgra) {
        CHECK(largest == 0);
      } else {
        CHECK(mean < kMeanTolerance);
        CHECK(largest < kMaxTolerance);
      }
      if (i == 0)
        std::printf("k4a reader %s: colour error mean %.3f/255, max %.1f/255\n", name.c_str(), mean * 255,
                    largest * 255);
    }
    CHECK(!reader.next_capture());
  }
}

TEST_CASE("k4a inspection: camera.json, colour and 16-bit depth PNGs, --frames bounds the work") {
  const std::filesystem::path file = write_recording("inspected", ColorFormat::mjpg, 3);
  const std::filesystem::path out = kOut / "inspected";
  std::filesystem::remove_all(out);
  CHECK(inspect_recording(file, 2, out).captures == 2);
  const nlohmann::json camera = config::read_json_file(out / "camera.json");
  CHECK(camera["config"]["color_format"] == "MJPG");
  CHECK(camera["config"]["color_resolution"] == nlohmann::json({1280, 720}));
  CHECK(camera["config"]["depth_mode"] == "NFOV_2X2BINNED");
  CHECK(camera["config"]["fps"] == 30);
  CHECK(camera["config"]["wired_sync_mode"] == "MASTER");
  CHECK(camera["config"]["start_offset_us"] == kStartUs);
  CHECK(camera["config"]["serial"] == "000442922212");
  CHECK(camera["color"]["fx"].get<double>() == Approx(611.3).epsilon(1e-12));
  CHECK(camera["color"]["p1"].get<double>() == Approx(4.0e-4).epsilon(1e-12));
  CHECK(camera["color"]["p2"].get<double>() == Approx(-1.5e-3).epsilon(1e-12));
  CHECK(camera["depth"]["width"] == 320);
  CHECK(camera["color_from_depth"][0][3].get<double>() == Approx(-0.032));
  REQUIRE(camera["captures"].size() == 2);
  CHECK(camera["captures"][1]["color_device_us"] == kStartUs + kPeriodUs);
  CHECK(camera["captures"][1]["depth_device_us"] == kStartUs + kPeriodUs + 200);
  CHECK(read_depth_png(out / "depth_0001.png").texels == test_depth(320, 288, 1).texels);
  CHECK(read_image(out / "color_0000.png").width == 1280);
  CHECK(!std::filesystem::exists(out / "color_0002.png"));
}

TEST_CASE("k4a reader: bad files are refused naming the file and what is wrong") {
  const std::filesystem::path good = write_recording("good", ColorFormat::mjpg, 3);

  SECTION("missing, or not Matroska") {
    CHECK_THROWS_WITH(RecordingReader(kOut / "nonexistent.mkv"), Contains("nonexistent.mkv': no such file"));
    const std::filesystem::path text = write_bytes("text.mkv", {'h', 'e', 'l', 'l', 'o', '\n'});
    CHECK_THROWS_WITH(RecordingReader(text), Contains("text.mkv': not a readable Matroska file"));
  }
  SECTION("truncated in the last capture") {
    std::vector<char> bytes = read_bytes(good);
    bytes.resize(bytes.size() - 100'000);  // inside the last depth image (184 kB)
    const std::filesystem::path cut = write_bytes("truncated.mkv", bytes);
    RecordingReader reader(cut);
    REQUIRE(reader.next_capture());
    REQUIRE(reader.next_capture());
    // The last capture's colour is whole; its depth is gone, and so the file is short.
    const std::optional<Capture> last = reader.next_capture();
    REQUIRE(last);
    CHECK(last->color_device_us == kStartUs + 2 * kPeriodUs);
    CHECK(!last->depth_device_us);
    CHECK_THROWS_WITH(reader.next_capture(),
                      Contains("truncated.mkv': the file ends at 66666 us of its 66866 us: truncated"));
  }
  SECTION("truncated in the header") {
    std::vector<char> bytes = read_bytes(good);
    bytes.resize(600);
    CHECK_THROWS_WITH(RecordingReader(write_bytes("header_only.mkv", bytes)),
                      Contains("header_only.mkv': the file ends before its first frame"));
  }
  SECTION("no calibration attachment") {
    const std::filesystem::path file = patched(good, "no_calibration.mkv", "calibration.json", "calibratiom.json");
    CHECK_THROWS_WITH(RecordingReader(file), Contains("no_calibration.mkv': no calibration attachment"));
  }
  SECTION("an unknown depth or colour mode") {
    CHECK_THROWS_WITH(RecordingReader(patched(good, "depth_mode.mkv", "NFOV_2X2BINNED", "NFOV_3X3BINNED")),
                      Contains("depth_mode.mkv': unknown depth mode K4A_DEPTH_MODE 'NFOV_3X3BINNED'"));
    CHECK_THROWS_WITH(RecordingReader(patched(good, "color_mode.mkv", "MJPG_720P", "MJPG_721P")),
                      Contains("color_mode.mkv': unknown colour mode K4A_COLOR_MODE 'MJPG_721P'"));
    // A track whose FourCC is not the mode's.
    CHECK_THROWS_WITH(RecordingReader(patched(good, "wrong_fourcc.mkv", "MJPG", "YUY2")),
                      Contains("COLOR track has FourCC 'YUY2', mode MJPG_720P records 'MJPG'"));
    // A mode that exists but is not the track's size.
    CHECK_THROWS_WITH(RecordingReader(patched(good, "wrong_size.mkv", "NFOV_2X2BINNED", "WFOV_2X2BINNED")),
                      Contains("DEPTH track is 320x288, mode WFOV_2X2BINNED is 512x512"));
  }
  SECTION("no frames") {
    const std::filesystem::path empty = write_recording("empty", ColorFormat::mjpg, 0);
    CHECK_THROWS_WITH(inspect_recording(empty, 5, kOut / "empty"),
                      Contains("empty.mkv': the file ends before its first frame (no captures"));
  }
  SECTION("a corrupt JPEG frame") {
    const std::vector<uint8_t> garbage(5000, 0x5a);
    RecordingReader reader(write_recording("garbage_jpeg", ColorFormat::mjpg, 3, 1, garbage));
    REQUIRE(reader.next_capture());
    CHECK_THROWS_WITH(reader.next_capture(),
                      Contains("garbage_jpeg.mkv': COLOR frame at device time 7033333 us is not a decodable JPEG"));
    std::vector<uint8_t> half = encode_mjpg(test_color(1280, 720, 1), kJpegQuality);
    half.resize(half.size() / 2);
    RecordingReader cut(write_recording("half_jpeg", ColorFormat::mjpg, 3, 1, half));
    REQUIRE(cut.next_capture());
    CHECK_THROWS_WITH(cut.next_capture(), Contains("half_jpeg.mkv': COLOR frame at device time 7033333 us"));
  }
  SECTION("a JPEG larger than its track is refused before it is decoded") {
    const std::vector<uint8_t> big = encode_mjpg(test_color(1920, 1080, 0), kJpegQuality);
    RecordingReader reader(write_recording("big_jpeg", ColorFormat::mjpg, 1, 0, big));
    CHECK_THROWS_WITH(reader.next_capture(), Contains("big_jpeg.mkv': COLOR frame at device time 7000000 us"));
  }
}

TEST_CASE("k4a reader: damaged bytes anywhere end in captures of the mode's size or in a RecordingError") {
  const std::filesystem::path good = write_recording("to_damage", ColorFormat::mjpg, 3);
  const std::vector<char> original = read_bytes(good);
  std::mt19937 random(47);
  size_t refused = 0, read = 0;
  for (int trial = 0; trial < 60; ++trial) {
    INFO("trial " << trial);
    std::vector<char> bytes = original;
    // Even trials damage the header (tracks, attachment, tags: the first 4 kB), odd ones the
    // captures after it.
    const bool header = trial % 2 == 0;
    for (int i = 0; i < 16; ++i) {
      const size_t at = header ? std::uniform_int_distribution<size_t>(0, 4095)(random)
                               : std::uniform_int_distribution<size_t>(4096, bytes.size() - 1)(random);
      bytes[at] = char(random());
    }
    const std::filesystem::path file = write_bytes("damaged.mkv", bytes);
    try {
      RecordingReader reader(file);
      for (int n = 0; n < 10; ++n) {
        const std::optional<Capture> capture = reader.next_capture();
        if (!capture) break;
        ++read;
        if (capture->color_device_us) CHECK(capture->color.texels.size() == size_t(1280) * 720 * 4);
        if (capture->depth_device_us) CHECK(capture->depth_mm.texels.size() == size_t(320) * 288);
      }
    } catch (const RecordingError& e) {
      ++refused;
      CHECK_THAT(e.what(), Contains("damaged.mkv'"));
    }
  }
  std::printf("k4a reader, damaged files: %zu of 60 refused, %zu captures read\n", refused, read);
  CHECK(refused > 0);
  CHECK(read > 0);
}

TEST_CASE("k4a reader: a capture whose colour or depth was dropped comes alone, the next ones whole") {
  std::filesystem::create_directories(kOut);
  const std::filesystem::path file = kOut / "dropped.mkv";
  {
    RecordingWriter writer(file, test_config(ColorFormat::mjpg));
    const auto jpeg = [](uint32_t i) { return encode_mjpg(test_color(1280, 720, i), kJpegQuality); };
    writer.write_capture(kStartUs, jpeg(0), test_depth(320, 288, 0));
    writer.write_capture(kStartUs + kPeriodUs, {}, test_depth(320, 288, 1));  // colour dropped
    writer.write_capture(kStartUs + 2 * kPeriodUs, jpeg(2), HostImage());     // depth dropped
    writer.write_capture(kStartUs + 3 * kPeriodUs, jpeg(3), test_depth(320, 288, 3));
    CHECK_THROWS_WITH(writer.write_capture(kStartUs + 4 * kPeriodUs, {}, HostImage()),
                      Contains("a capture without colour or depth"));
  }
  RecordingReader reader(file);
  std::vector<Capture> captures;
  while (std::optional<Capture> capture = reader.next_capture()) captures.push_back(std::move(*capture));
  REQUIRE(captures.size() == 4);
  CHECK(captures[0].color_device_us == kStartUs);
  CHECK(captures[0].depth_device_us == kStartUs + 200);
  CHECK(!captures[1].color_device_us);
  CHECK(captures[1].color.width == 0);
  CHECK(captures[1].depth_device_us == kStartUs + kPeriodUs + 200);
  CHECK(captures[1].depth_mm.texels == test_depth(320, 288, 1).texels);
  CHECK(captures[2].color_device_us == kStartUs + 2 * kPeriodUs);
  CHECK(!captures[2].depth_device_us);
  CHECK(captures[2].color.width == 1280);
  CHECK(captures[3].color_device_us == kStartUs + 3 * kPeriodUs);
  CHECK(captures[3].depth_mm.texels == test_depth(320, 288, 3).texels);
}
