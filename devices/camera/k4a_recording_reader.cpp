#include "camera/k4a_recording_reader.h"

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
}

#include <algorithm>
#include <array>
#include <charconv>
#include <ctime>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

namespace rt::camera::k4a {

namespace {

// A calibration.json is a few kilobytes; anything far larger is not one.
constexpr int kMaxCalibrationBytes = 1 << 20;

std::string av_error(int code) {
  char text[AV_ERROR_MAX_STRING_SIZE] = {};
  av_strerror(code, text, sizeof(text));
  return text;
}

struct PacketDeleter {
  void operator()(AVPacket* p) const { av_packet_free(&p); }
};
using Packet = std::unique_ptr<AVPacket, PacketDeleter>;

// A tag as libavformat hands it on: global tags in the file's metadata, track tags in the
// stream's, some with their target type as a prefix ("TRACK/K4A_COLOR_MODE").
std::optional<std::string> find_tag(const AVFormatContext* format, const char* name) {
  const auto search = [&](const AVDictionary* dictionary) -> std::optional<std::string> {
    const AVDictionaryEntry* entry = nullptr;
    while ((entry = av_dict_get(dictionary, "", entry, AV_DICT_IGNORE_SUFFIX))) {
      const std::string_view key = entry->key;
      if (key == name ||
          (key.size() > std::strlen(name) && key.ends_with(name) && key[key.size() - std::strlen(name) - 1] == '/'))
        return std::string(entry->value);
    }
    return std::nullopt;
  };
  if (auto value = search(format->metadata)) return value;
  for (unsigned i = 0; i < format->nb_streams; ++i)
    if (auto value = search(format->streams[i]->metadata)) return value;
  return std::nullopt;
}

template <typename T>
std::optional<T> parse_integer(const std::string& text) {
  T value{};
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size()) return std::nullopt;
  return value;
}

// 'MJPG', or the number when its bytes are not all printable.
std::string fourcc_text(uint32_t fourcc) {
  std::string text;
  for (int i = 0; i < 4; ++i) {
    const char c = char(fourcc >> (8 * i));
    if (c < 0x20 || c > 0x7e) {
      char hex[16];
      std::snprintf(hex, sizeof(hex), "0x%08x", fourcc);
      return hex;
    }
    text += c;
  }
  return "'" + text + "'";
}

double ms_since(double start_ms) { return thread_cpu_ms() - start_ms; }

}  // namespace

struct RecordingReader::Demuxer {
  std::string where;  // the file, quoted, as errors name it
  AVFormatContext* format = nullptr;
  int color_stream = -1, depth_stream = -1;
  std::unique_ptr<ColorDecoder> color;
  Packet pending;              // read ahead: the first packet of the next capture
  int64_t last_block_us = -1;  // timecode of the latest COLOR or DEPTH block read
  std::string truncation;      // why the file ended early, once it has
  bool ended = false;

  ~Demuxer() { avformat_close_input(&format); }

  int64_t timecode_us(const AVPacket& packet) const {
    const AVStream* stream = format->streams[packet.stream_index];
    const int64_t ts = packet.pts != AV_NOPTS_VALUE ? packet.pts : packet.dts;
    return av_rescale_q(ts, stream->time_base, AVRational{1, 1000000});
  }

  // A file cut short loses its last blocks whole: the last block read must be at the duration
  // the header declares (the time of the last block written), when it declares one.
  void check_complete() {
    if (format->duration == AV_NOPTS_VALUE || format->duration <= 0) return;
    const int64_t declared_us = av_rescale_q(format->duration, AV_TIME_BASE_Q, AVRational{1, 1000000});
    if (last_block_us < declared_us)
      truncation = where + ": the file ends at " + std::to_string(last_block_us) + " us of its " +
                   std::to_string(declared_us) + " us: truncated";
  }

  // The next COLOR or DEPTH packet, other tracks (IR, IMU) skipped; empty at the end.
  Packet read_packet() {
    if (pending) return std::move(pending);
    while (!ended) {
      Packet packet(av_packet_alloc());
      const int error = av_read_frame(format, packet.get());
      if (error == AVERROR_EOF) {
        ended = true;
        check_complete();
        break;
      }
      if (error < 0) throw RecordingError(where + ": the file is truncated or damaged (" + av_error(error) + ")");
      if (packet->stream_index == color_stream || packet->stream_index == depth_stream) {
        last_block_us = std::max(last_block_us, timecode_us(*packet));
        return packet;
      }
    }
    return nullptr;
  }

  HostImage decode_depth(const AVPacket& packet, DepthMode mode, const std::string& frame_name, DecodeTimes& times) const {
    const double start = thread_cpu_ms();
    const SensorCut& cut = sensor_cut(mode);
    const size_t expected = size_t(cut.output_width) * cut.output_height * 2;
    if ((packet.flags & AV_PKT_FLAG_CORRUPT) || size_t(packet.size) != expected)
      throw RecordingError(frame_name + " has " + std::to_string(packet.size) + " bytes, " +
                           std::string(depth_mode_name(mode)) + " needs " + std::to_string(expected) +
                           " (truncated or damaged)");
    HostImage depth(cut.output_width, cut.output_height, PixelFormat::R16U);
    for (size_t i = 0; i < depth.texels.size(); ++i)
      depth.texels[i] = float((uint32_t(packet.data[2 * i]) << 8) | packet.data[2 * i + 1]);  // big-endian
    times.to_host_ms += ms_since(start);
    return depth;
  }

  HostImage decode_color(const AVPacket& packet, const std::string& frame_name, DecodeTimes& times) {
    if (packet.flags & AV_PKT_FLAG_CORRUPT) throw RecordingError(frame_name + " is truncated or damaged");
    try {
      return color->decode(packet.data, size_t(std::max(0, packet.size)), frame_name, times);
    } catch (const ImageError& error) {
      throw RecordingError(error.what());
    }
  }
};

RecordingReader::RecordingReader(const std::filesystem::path& path)
    : path_(path), demuxer_(std::make_unique<Demuxer>()) {
  const std::string where = "'" + path.string() + "'";
  const auto fail = [&](const std::string& what) { return RecordingError(where + ": " + what); };
  // Our errors say what is wrong; the libraries' own messages would only repeat it.
  av_log_set_level(AV_LOG_FATAL);
  if (!std::filesystem::is_regular_file(path)) throw fail("no such file");
  Demuxer& d = *demuxer_;
  d.where = where;
  if (const int error = avformat_open_input(&d.format, path.c_str(), nullptr, nullptr); error < 0) {
    // The demuxer reads the header up to the first cluster: a file without one ends there.
    if (error == AVERROR_EOF)
      throw fail("the file ends before its first frame (no captures, or truncated in its header)");
    throw fail("not a readable Matroska file (" + av_error(error) + ")");
  }
  if (std::string_view(d.format->iformat->name).find("matroska") == std::string_view::npos)
    throw fail(std::string("not a Matroska file (") + d.format->iformat->name + ")");

  // Tracks: the recorder names them COLOR and DEPTH.
  const AVStream* attachment = nullptr;
  for (unsigned i = 0; i < d.format->nb_streams; ++i) {
    const AVStream* stream = d.format->streams[i];
    const AVDictionaryEntry* title = av_dict_get(stream->metadata, "title", nullptr, 0);
    if (stream->codecpar->codec_type == AVMEDIA_TYPE_VIDEO && title) {
      if (std::string_view(title->value) == "COLOR" && d.color_stream < 0) d.color_stream = int(i);
      if (std::string_view(title->value) == "DEPTH" && d.depth_stream < 0) d.depth_stream = int(i);
    }
    const AVDictionaryEntry* filename = av_dict_get(stream->metadata, "filename", nullptr, 0);
    if (stream->codecpar->codec_type == AVMEDIA_TYPE_ATTACHMENT && filename &&
        std::string_view(filename->value) == find_tag(d.format, "K4A_CALIBRATION_FILE").value_or("calibration.json"))
      attachment = stream;
  }
  if (d.color_stream < 0 && d.depth_stream < 0) throw fail("no COLOR or DEPTH track: not a k4a recording");
  if (d.color_stream < 0) throw fail("no COLOR track (recordings without colour are not supported)");
  if (d.depth_stream < 0) throw fail("no DEPTH track (recordings without depth are not supported)");

  // Modes, from the tags, checked against the tracks.
  const std::optional<std::string> color_mode = find_tag(d.format, "K4A_COLOR_MODE");
  if (!color_mode) throw fail("no K4A_COLOR_MODE tag");
  const std::optional<ColorMode> mode = color_mode_from_tag(*color_mode);
  if (!mode) throw fail("unknown colour mode K4A_COLOR_MODE '" + *color_mode + "'");
  info_.color_format = mode->format;
  info_.color_resolution = mode->resolution;
  const std::optional<std::string> depth_mode = find_tag(d.format, "K4A_DEPTH_MODE");
  if (!depth_mode) throw fail("no K4A_DEPTH_MODE tag (required with a DEPTH track)");
  const std::optional<DepthMode> depth = depth_mode_from_name(*depth_mode);
  if (!depth) throw fail("unknown depth mode K4A_DEPTH_MODE '" + *depth_mode + "'");
  info_.depth_mode = *depth;

  const auto check_track = [&](int index, const char* name, const SensorCut& cut, uint32_t fourcc,
                               const std::string& mode_name) {
    const AVCodecParameters* codec = d.format->streams[index]->codecpar;
    if (codec->codec_tag != fourcc)
      throw fail(std::string(name) + " track has FourCC " + fourcc_text(codec->codec_tag) + ", mode " + mode_name +
                 " records " + fourcc_text(fourcc));
    if (uint32_t(codec->width) != cut.output_width || uint32_t(codec->height) != cut.output_height)
      throw fail(std::string(name) + " track is " + std::to_string(codec->width) + "x" + std::to_string(codec->height) +
                 ", mode " + mode_name + " is " + std::to_string(cut.output_width) + "x" +
                 std::to_string(cut.output_height));
  };
  check_track(d.color_stream, "COLOR", sensor_cut(info_.color_resolution), color_fourcc(info_.color_format),
              *color_mode);
  check_track(d.depth_stream, "DEPTH", sensor_cut(info_.depth_mode), kDepthFourcc, *depth_mode);

  const AVRational rate = d.format->streams[d.color_stream]->avg_frame_rate;
  const std::optional<uint32_t> fps = rate.num > 0 && rate.den > 0
                                          ? frame_rate_for_period(uint64_t(std::llround(1e9 * rate.den / rate.num)))
                                          : std::nullopt;
  if (!fps) throw fail("COLOR track's frame duration is not a 5, 15 or 30 fps period");
  info_.fps = *fps;

  // Timing and identity tags; each is optional in the SDK's playback but must parse when present.
  if (auto text = find_tag(d.format, "K4A_DEPTH_DELAY_NS")) {
    const auto value = parse_integer<int64_t>(*text);
    if (!value) throw fail("K4A_DEPTH_DELAY_NS '" + *text + "' is not an integer");
    info_.depth_delay_ns = *value;
  }
  if (auto text = find_tag(d.format, "K4A_WIRED_SYNC_MODE")) {
    if (*text == "STANDALONE")
      info_.wired_sync = WiredSyncMode::standalone;
    else if (*text == "MASTER")
      info_.wired_sync = WiredSyncMode::master;
    else if (*text == "SUBORDINATE")
      info_.wired_sync = WiredSyncMode::subordinate;
    else
      throw fail("unknown K4A_WIRED_SYNC_MODE '" + *text + "'");
  }
  if (auto text = find_tag(d.format, "K4A_SUBORDINATE_DELAY_NS")) {
    const auto value = parse_integer<uint64_t>(*text);
    if (!value) throw fail("K4A_SUBORDINATE_DELAY_NS '" + *text + "' is not an unsigned integer");
    info_.subordinate_delay_ns = *value;
  }
  if (auto text = find_tag(d.format, "K4A_START_OFFSET_NS")) {
    const auto value = parse_integer<uint64_t>(*text);
    if (!value) throw fail("K4A_START_OFFSET_NS '" + *text + "' is not an unsigned integer");
    info_.start_offset_us = *value / 1000;
  }
  info_.serial = find_tag(d.format, "K4A_DEVICE_SERIAL_NUMBER").value_or("");

  // The factory calibration at the recorded modes.
  if (!attachment) throw fail("no calibration attachment (calibration.json): the intrinsics are unknown");
  const AVCodecParameters* attached = attachment->codecpar;
  if (!attached->extradata || attached->extradata_size <= 0 || attached->extradata_size > kMaxCalibrationBytes)
    throw fail("calibration.json attachment is empty or larger than 1 MiB");
  const std::string_view text(reinterpret_cast<const char*>(attached->extradata), size_t(attached->extradata_size));
  try {
    info_.calibration = parse_calibration_json(text, where);
    info_.color = color_intrinsics(info_.calibration.color, info_.color_resolution);
    info_.depth = depth_intrinsics(info_.calibration.depth, info_.depth_mode);
  } catch (const CalibrationError& e) {
    throw RecordingError(e.what());
  }

  try {
    d.color = std::make_unique<ColorDecoder>(info_.color_format, info_.color_resolution);
  } catch (const ImageError& error) {
    throw fail(error.what());
  }
}

RecordingReader::~RecordingReader() = default;

// The packets of the next capture: a COLOR and a DEPTH block apart by the depth delay, within
// half a frame period, or one of them alone when the device dropped the other.
RecordingReader::CapturePackets RecordingReader::read_capture_packets() {
  Demuxer& d = *demuxer_;
  const uint64_t half_period_us = frame_period_ns(info_.fps) / 2000;
  CapturePackets packets;
  while (Packet packet = d.read_packet()) {
    const bool is_color = packet->stream_index == d.color_stream;
    std::shared_ptr<AVPacket>& slot = is_color ? packets.color : packets.depth;
    const std::shared_ptr<AVPacket>& other = is_color ? packets.depth : packets.color;
    bool belongs = !slot;
    if (belongs && other) {
      const int64_t color_us = int64_t(device_us(is_color ? *packet : *other));
      const int64_t depth_us = int64_t(device_us(is_color ? *other : *packet)) - info_.depth_delay_ns / 1000;
      belongs = uint64_t(std::llabs(depth_us - color_us)) < half_period_us;
    }
    if (!belongs) {
      d.pending = std::move(packet);
      break;
    }
    slot = std::shared_ptr<AVPacket>(packet.release(), PacketDeleter{});
    if (packets.color && packets.depth) break;
  }
  // What was read before the cut is returned first; the next call reports the cut.
  if (!packets.color && !packets.depth && !d.truncation.empty()) throw RecordingError(d.truncation);
  return packets;
}

uint64_t RecordingReader::device_us(const AVPacket& packet) const {
  return uint64_t(std::max<int64_t>(0, demuxer_->timecode_us(packet))) + info_.start_offset_us;
}

std::optional<CaptureTimes> RecordingReader::skip_capture() {
  const CapturePackets packets = read_capture_packets();
  if (!packets.color && !packets.depth) return std::nullopt;
  CaptureTimes times;
  if (packets.color) times.color_device_us = device_us(*packets.color);
  if (packets.depth) times.depth_device_us = device_us(*packets.depth);
  return times;
}

std::optional<Capture> RecordingReader::next_capture() {
  Demuxer& d = *demuxer_;
  const double start = thread_cpu_ms();
  const CapturePackets packets = read_capture_packets();
  times_.demux_ms += ms_since(start);
  const std::shared_ptr<AVPacket>& color = packets.color;
  const std::shared_ptr<AVPacket>& depth = packets.depth;
  if (!color && !depth) return std::nullopt;
  ++times_.captures;

  Capture capture;
  const auto frame_name = [&](const char* track, uint64_t time) {
    return d.where + ": " + track + " frame at device time " + std::to_string(time) + " us";
  };
  if (depth) {
    capture.depth_device_us = device_us(*depth);
    capture.depth_mm = d.decode_depth(*depth, info_.depth_mode, frame_name("DEPTH", *capture.depth_device_us), times_);
  }
  if (color) {
    capture.color_device_us = device_us(*color);
    capture.color = d.decode_color(*color, frame_name("COLOR", *capture.color_device_us), times_);
  }
  return capture;
}

}  // namespace rt::camera::k4a
