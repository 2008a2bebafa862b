// k4a recordings as we write them (devices/camera/k4a_recording_writer.h), read back by
// independent Matroska readers (mkvinfo; libavformat, as it reads real recordings) and held to the
// rules the SDK's playback applies: video
// tracks COLOR and DEPTH of codec V_MS/VFW/FOURCC with a 40-byte BITMAPINFOHEADER naming the
// FourCC, a DefaultDuration of a 5, 15 or 30 fps period, sizes of the recorded modes, the
// K4A_DEPTH_MODE tag, the track-UID tags pointing at the tracks, the calibration attachment,
// and block timecodes in microseconds from the first capture.
#include <catch2/catch.hpp>

#include <cstdio>
#include <filesystem>
#include <map>
#include <regex>
#include <sstream>

#include "camera/k4a_recording_writer.h"

extern "C" {
#include <libavformat/avformat.h>
#include "support/output_dir.h"
}

using namespace rt;
using namespace rt::camera::k4a;
using Catch::Matchers::Contains;

namespace {

const std::filesystem::path kOutK4aRecordingWriter = rt::test::output_dir("test_k4a_recording_writer");

HostImage gradient_rgba(uint32_t width, uint32_t height, float shift) {
  HostImage image(width, height, PixelFormat::RGBA8);
  for (uint32_t y = 0; y < height; ++y)
    for (uint32_t x = 0; x < width; ++x) {
      image.at(x, y, 0) = std::round(255.0f * x / width) / 255.0f;
      image.at(x, y, 1) = std::round(255.0f * y / height) / 255.0f;
      image.at(x, y, 2) = std::round(255.0f * shift) / 255.0f;
      image.at(x, y, 3) = 1.0f;
    }
  return image;
}

HostImage depth_ramp(uint32_t width, uint32_t height, uint32_t offset) {
  HostImage depth(width, height, PixelFormat::R16U);
  for (uint32_t y = 0; y < height; ++y)
    for (uint32_t x = 0; x < width; ++x) depth.at(x, y) = float((x * 7 + y * 13 + offset) % 4000);
  return depth;
}

std::string run(const std::string& command) {
  std::string output;
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  REQUIRE(pipe);
  char buffer[4096];
  while (size_t n = fread(buffer, 1, sizeof(buffer), pipe)) output.append(buffer, n);
  pclose(pipe);
  return output;
}

// mkvinfo's tree, one element a line ("|  + Codec ID: V_MS/VFW/FOURCC"): the tracks' fields by
// track name, and the tags as name -> (value, target line).
struct MkvInfo {
  std::map<std::string, std::map<std::string, std::string>> tracks;
  std::map<std::string, std::string> tags;
  std::map<std::string, std::string> tag_targets;
  std::vector<std::pair<int, std::string>> blocks;  // track number, timestamp text
  std::string attachment_uid, attachment_name;
  size_t attachment_size = 0;
};

MkvInfo parse_mkvinfo(const std::string& text) {
  MkvInfo info;
  std::istringstream lines(text);
  std::string line;
  std::map<std::string, std::string> track;
  std::string section, target, tag_name;
  const std::regex field(R"(^[| ]*\+ ([^:]+): (.*)$)");
  const std::regex block(R"(Simple block: key, track number (\d+), 1 frame\(s\), timestamp (\S+))");
  const auto end_track = [&] {
    if (track.count("Name")) info.tracks[track["Name"]] = track;
    track.clear();
  };
  while (std::getline(lines, line)) {
    std::smatch m;
    if (line.find("+ Track") != std::string::npos && line.find(":") == std::string::npos) {
      end_track();
      section = "track";
    } else if (line.find("+ Attached") != std::string::npos) {
      end_track();
      section = "attachment";
    } else if (line.find("+ Tag") != std::string::npos && line.find(":") == std::string::npos) {
      end_track();
      section = "tag";
      target.clear();
    } else if (std::regex_search(line, m, block)) {
      info.blocks.push_back({std::stoi(m[1]), m[2]});
    } else if (std::regex_match(line, m, field)) {
      const std::string key = m[1], value = m[2];
      if (section == "track") track[key] = value;
      if (section == "attachment" && key == "File UID") info.attachment_uid = value;
      if (section == "attachment" && key == "File name") info.attachment_name = value;
      if (section == "attachment" && key == "File data") info.attachment_size = std::stoul(value.substr(5));
      if (section == "tag" && (key == "Track UID" || key == "Attachment UID")) target = key + " " + value;
      if (section == "tag" && key == "Name") tag_name = value;
      if (section == "tag" && key == "String") {
        info.tags[tag_name] = value;
        info.tag_targets[tag_name] = target;
      }
    }
  }
  end_track();
  return info;
}

MkvInfo mkvinfo(const std::filesystem::path& file) {
  const std::string program = REMOTETOUCH_MKVINFO;
  if (program.empty()) FAIL("mkvinfo is not installed (Debian mkvtoolnix, scripts/packages.txt)");
  return parse_mkvinfo(run(program + " -v '" + file.string() + "'"));
}

RecordingConfig test_config_k4a_recording_writer() {
  RecordingConfig config;
  config.color_resolution = ColorResolution::p720;
  config.depth_mode = DepthMode::nfov_2x2_binned;
  config.fps = 30;
  config.depth_delay_ns = -120000;
  config.wired_sync = WiredSyncMode::subordinate;
  config.subordinate_delay_ns = 160000;
  config.serial = "000261501812";
  CameraIntrinsics color;
  color.width = 1280, color.height = 720, color.fx = color.fy = 605.0, color.cx = 641.2, color.cy = 362.9;
  CameraIntrinsics depth;
  depth.width = 320, depth.height = 288, depth.fx = depth.fy = 252.4, depth.cx = 160.7, depth.cy = 166.1;
  config.calibration.color = color_sensor_for(color, ColorResolution::p720);
  config.calibration.depth = depth_sensor_for(depth, DepthMode::nfov_2x2_binned);
  return config;
}

}  // namespace

TEST_CASE("k4a writer: the track headers, tags and attachment as mkvinfo reads them pass the SDK's playback rules") {
  std::filesystem::create_directories(kOutK4aRecordingWriter);
  const std::filesystem::path file = kOutK4aRecordingWriter / "rules.mkv";
  const RecordingConfig config = test_config_k4a_recording_writer();
  // A device clock that started long before the recording; depth 120 us before colour.
  const uint64_t start_us = 5'000'123;
  {
    RecordingWriter writer(file, config);
    for (uint32_t i = 0; i < 3; ++i)
      writer.write_capture(start_us + i * 33'333, encode_mjpg(gradient_rgba(1280, 720, 0.1f * i), 90),
                           depth_ramp(320, 288, i));
    writer.close();
    CHECK(writer.captures_written() == 3);
  }
  const MkvInfo info = mkvinfo(file);
  REQUIRE(info.tracks.count("COLOR"));
  REQUIRE(info.tracks.count("DEPTH"));
  const auto& color = info.tracks.at("COLOR");
  const auto& depth = info.tracks.at("DEPTH");
  for (const auto* track : {&color, &depth}) {
    CHECK(track->at("Track type") == "video");
    CHECK(track->at("Codec ID") == "V_MS/VFW/FOURCC");
    // 33333333 ns: 1 s / 30, truncated as the SDK writes and reads it.
    CHECK_THAT(track->at("Default duration"), Contains("00:00:00.033333333"));
  }
  CHECK_THAT(color.at("Codec's private data"), Contains("size 40 (FourCC: 0x4d4a5047 \"MJPG\")"));
  CHECK_THAT(depth.at("Codec's private data"), Contains("size 40 (FourCC: 0x62313667 \"b16g\")"));
  CHECK(color.at("Pixel width") == "1280");
  CHECK(color.at("Pixel height") == "720");
  CHECK(depth.at("Pixel width") == "320");
  CHECK(depth.at("Pixel height") == "288");

  CHECK(info.tags.at("K4A_COLOR_MODE") == "MJPG_720P");
  CHECK(info.tags.at("K4A_DEPTH_MODE") == "NFOV_2X2BINNED");
  CHECK(info.tags.at("K4A_DEPTH_DELAY_NS") == "-120000");
  CHECK(info.tags.at("K4A_WIRED_SYNC_MODE") == "SUBORDINATE");
  CHECK(info.tags.at("K4A_SUBORDINATE_DELAY_NS") == "160000");
  CHECK(info.tags.at("K4A_DEVICE_SERIAL_NUMBER") == "000261501812");
  // The first block is the depth image, 120 us before the colour: the file starts there.
  CHECK(info.tags.at("K4A_START_OFFSET_NS") == std::to_string((start_us - 120) * 1000));
  // Track-UID tags hold their track's UID and target it.
  CHECK(info.tags.at("K4A_COLOR_TRACK") == color.at("Track UID"));
  CHECK(info.tag_targets.at("K4A_COLOR_TRACK") == "Track UID " + color.at("Track UID"));
  CHECK(info.tags.at("K4A_DEPTH_TRACK") == depth.at("Track UID"));
  CHECK(info.tag_targets.at("K4A_DEPTH_MODE") == "Track UID " + depth.at("Track UID"));
  CHECK(info.tags.at("K4A_CALIBRATION_FILE") == "calibration.json");
  CHECK(info.attachment_name == "calibration.json");
  CHECK(info.tag_targets.at("K4A_CALIBRATION_FILE") == "Attachment UID " + info.attachment_uid);
  CHECK(info.attachment_size > 500);

  // Blocks in time order, microsecond timecodes from the first capture: depth at 0, colour at
  // 120 us, then every 33333 us.
  const std::vector<std::pair<int, std::string>> expected = {{2, "00:00:00.000000000"}, {1, "00:00:00.000120000"},
                                                             {2, "00:00:00.033333000"}, {1, "00:00:00.033453000"},
                                                             {2, "00:00:00.066666000"}, {1, "00:00:00.066786000"}};
  CHECK(info.blocks == expected);
}

TEST_CASE("k4a writer: the frame period of each k4a rate, and bad arguments refused") {
  std::filesystem::create_directories(kOutK4aRecordingWriter);
  for (uint32_t fps : {5u, 15u}) {
    RecordingConfig config = test_config_k4a_recording_writer();
    config.fps = fps;
    const std::filesystem::path file = kOutK4aRecordingWriter / ("rate" + std::to_string(fps) + ".mkv");
    {
      RecordingWriter writer(file, config);
      writer.write_capture(1000, encode_mjpg(gradient_rgba(1280, 720, 0.5f), 80), depth_ramp(320, 288, 0));
    }
    CHECK_THAT(mkvinfo(file).tracks.at("COLOR").at("Default duration"),
               Contains(fps == 5 ? "00:00:00.200000000" : "00:00:00.066666666"));
  }
  RecordingConfig config = test_config_k4a_recording_writer();
  config.fps = 25;
  CHECK_THROWS_WITH(RecordingWriter(kOutK4aRecordingWriter / "bad.mkv", config), Contains("25 fps is not a k4a rate"));
  RecordingWriter writer(kOutK4aRecordingWriter / "bad.mkv", test_config_k4a_recording_writer());
  CHECK_THROWS_WITH(
      writer.write_capture(1000, encode_mjpg(gradient_rgba(1280, 720, 0.5f), 80), depth_ramp(640, 576, 0)),
      Contains("depth must be r16ui 320x288 (NFOV_2X2BINNED), got r16ui 640x576"));
  writer.write_capture(1000, encode_mjpg(gradient_rgba(1280, 720, 0.5f), 80), depth_ramp(320, 288, 0));
  CHECK_THROWS_WITH(
      writer.write_capture(1000, encode_mjpg(gradient_rgba(1280, 720, 0.5f), 80), depth_ramp(320, 288, 0)),
      Contains("capture times must increase"));
  RecordingConfig bgra = test_config_k4a_recording_writer();
  bgra.color_format = ColorFormat::bgra;
  RecordingWriter raw(kOutK4aRecordingWriter / "bad_bgra.mkv", bgra);
  CHECK_THROWS_WITH(raw.write_capture(1000, encode_bgra(gradient_rgba(640, 360, 0.5f)), depth_ramp(320, 288, 0)),
                    Contains("BGRA colour of 921600 bytes, the mode needs 3686400"));
  CHECK_THROWS_WITH(RecordingWriter("/nonexistent-dir/x.mkv", test_config_k4a_recording_writer()),
                    Contains("cannot create '/nonexistent-dir/x.mkv'"));
}

TEST_CASE("k4a writer: libavformat sees MJPG colour, gray16be depth, 30 fps and the calibration attachment") {
  std::filesystem::create_directories(kOutK4aRecordingWriter);
  const std::filesystem::path file = kOutK4aRecordingWriter / "libavformat.mkv";
  {
    RecordingWriter writer(file, test_config_k4a_recording_writer());
    for (uint32_t i = 0; i < 2; ++i)
      writer.write_capture(1'000'000 + i * 33'333, encode_mjpg(gradient_rgba(1280, 720, 0.2f), 90),
                           depth_ramp(320, 288, i));
  }
  AVFormatContext* format = nullptr;
  REQUIRE(avformat_open_input(&format, file.c_str(), nullptr, nullptr) == 0);
  REQUIRE(avformat_find_stream_info(format, nullptr) >= 0);
  const AVStream *color = nullptr, *depth = nullptr, *attachment = nullptr;
  for (unsigned i = 0; i < format->nb_streams; ++i) {
    const AVStream* stream = format->streams[i];
    const AVDictionaryEntry* title = av_dict_get(stream->metadata, "title", nullptr, 0);
    if (title && std::string(title->value) == "COLOR") color = stream;
    if (title && std::string(title->value) == "DEPTH") depth = stream;
    if (stream->codecpar->codec_type == AVMEDIA_TYPE_ATTACHMENT) attachment = stream;
  }
  REQUIRE(color);
  REQUIRE(depth);
  REQUIRE(attachment);
  CHECK(color->codecpar->codec_id == AV_CODEC_ID_MJPEG);
  CHECK(color->codecpar->codec_tag == 0x47504A4Du);  // "MJPG"
  CHECK(color->codecpar->width == 1280);
  CHECK(depth->codecpar->codec_id == AV_CODEC_ID_RAWVIDEO);
  CHECK(depth->codecpar->codec_tag == 0x67363162u);  // "b16g"
  CHECK(depth->codecpar->format == AV_PIX_FMT_GRAY16BE);
  CHECK(depth->codecpar->height == 288);
  CHECK(color->avg_frame_rate.num == 30);
  CHECK(color->avg_frame_rate.den == 1);
  CHECK(std::string(av_dict_get(attachment->metadata, "filename", nullptr, 0)->value) == "calibration.json");
  CHECK(std::string(av_dict_get(format->metadata, "K4A_WIRED_SYNC_MODE", nullptr, 0)->value) == "SUBORDINATE");
  CHECK(std::string(av_dict_get(depth->metadata, "K4A_DEPTH_MODE", nullptr, 0)->value) == "NFOV_2X2BINNED");
  avformat_close_input(&format);
}
