#include "camera/k4a_recording_reader.h"

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/opt.h>
#include <libswscale/swscale.h>
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
struct FrameDeleter {
  void operator()(AVFrame* f) const { av_frame_free(&f); }
};
struct CodecDeleter {
  void operator()(AVCodecContext* c) const { avcodec_free_context(&c); }
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

HostImage rgba_from(const uint8_t* pixels, uint32_t width, uint32_t height) {
  // A table of the 256 values (each exactly byte / 255) instead of a division per channel.
  static const std::array<float, 256> kUnit = [] {
    std::array<float, 256> unit{};
    for (size_t i = 0; i < unit.size(); ++i) unit[i] = float(i) / 255.0f;
    return unit;
  }();
  HostImage image;
  image.width = width;
  image.height = height;
  image.format = PixelFormat::RGBA8;
  const size_t count = size_t(width) * height * 4;
  image.texels.reserve(count);
  for (size_t i = 0; i < count; ++i) image.texels.push_back(kUnit[pixels[i]]);
  return image;
}

// The decoding thread's own CPU time: stage figures that other processes' load does not inflate.
double thread_cpu_ms() {
  timespec now{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
  return double(now.tv_sec) * 1e3 + double(now.tv_nsec) * 1e-6;
}
double ms_since(double start_ms) { return thread_cpu_ms() - start_ms; }

}  // namespace

struct RecordingReader::Demuxer {
  std::string where;  // the file, quoted, as errors name it
  AVFormatContext* format = nullptr;
  int color_stream = -1, depth_stream = -1;
  std::unique_ptr<AVCodecContext, CodecDeleter> jpeg;
  std::unique_ptr<AVFrame, FrameDeleter> frame{av_frame_alloc()};
  SwsContext* scaler = nullptr;
  std::vector<uint8_t> rgba;
  Packet pending;              // read ahead: the first packet of the next capture
  int64_t last_block_us = -1;  // timecode of the latest COLOR or DEPTH block read
  std::string truncation;      // why the file ended early, once it has
  bool ended = false;

  ~Demuxer() {
    sws_freeContext(scaler);
    avformat_close_input(&format);
  }

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

  HostImage decode_color(const AVPacket& packet, ColorFormat format, ColorResolution resolution,
                         const std::string& frame_name, DecodeTimes& times) {
    double start = thread_cpu_ms();
    const SensorCut& cut = sensor_cut(resolution);
    const int w = int(cut.output_width), h = int(cut.output_height);
    if (packet.flags & AV_PKT_FLAG_CORRUPT) throw RecordingError(frame_name + " is truncated or damaged");
    AVPixelFormat source_format = AV_PIX_FMT_NONE;
    const uint8_t* planes[4] = {};
    int strides[4] = {};
    size_t expected = 0;
    switch (format) {
      case ColorFormat::mjpg: {
        int error = avcodec_send_packet(jpeg.get(), &packet);
        if (error >= 0) error = avcodec_receive_frame(jpeg.get(), frame.get());
        if (error < 0 || (frame->flags & AV_FRAME_FLAG_CORRUPT) || frame->decode_error_flags)
          throw RecordingError(frame_name + " is not a decodable JPEG (" +
                               (error < 0 ? av_error(error) : std::string("decode errors")) + ")");
        if (frame->width != w || frame->height != h)
          throw RecordingError(frame_name + " decodes to " + std::to_string(frame->width) + "x" +
                               std::to_string(frame->height) + ", the track is " + std::to_string(w) + "x" +
                               std::to_string(h));
        source_format = AVPixelFormat(frame->format);
        times.color_decode_ms += ms_since(start);
        start = thread_cpu_ms();
        for (int i = 0; i < 4; ++i) planes[i] = frame->data[i], strides[i] = frame->linesize[i];
        break;
      }
      case ColorFormat::nv12:
        source_format = AV_PIX_FMT_NV12;
        expected = size_t(w) * h * 3 / 2;
        planes[0] = packet.data, strides[0] = w;
        planes[1] = packet.data + size_t(w) * h, strides[1] = w;
        break;
      case ColorFormat::yuy2:
        source_format = AV_PIX_FMT_YUYV422;
        expected = size_t(w) * h * 2;
        planes[0] = packet.data, strides[0] = w * 2;
        break;
      case ColorFormat::bgra:
        source_format = AV_PIX_FMT_BGRA;
        expected = size_t(w) * h * 4;
        planes[0] = packet.data, strides[0] = w * 4;
        break;
    }
    if (format != ColorFormat::mjpg && size_t(packet.size) != expected)
      throw RecordingError(frame_name + " has " + std::to_string(packet.size) + " bytes, " +
                           std::string(color_format_name(format)) + " " + std::to_string(w) + "x" + std::to_string(h) +
                           " needs " + std::to_string(expected) + " (truncated or damaged)");
    // Chroma interpolated at full resolution: without it the colour is biased by more than a level.
    // The exactly rounded path would cost about three times as long for a fraction of a level.
    scaler = sws_getCachedContext(scaler, w, h, source_format, w, h, AV_PIX_FMT_RGBA,
                                  SWS_BILINEAR | SWS_FULL_CHR_H_INT, nullptr,
                                  nullptr, nullptr);
    if (!scaler) throw RecordingError(frame_name + ": no conversion from its pixel format to RGBA");
    rgba.resize(size_t(w) * h * 4);
    uint8_t* out[4] = {rgba.data(), nullptr, nullptr, nullptr};
    int out_strides[4] = {w * 4, 0, 0, 0};
    sws_scale(scaler, planes, strides, 0, h, out, out_strides);
    times.color_convert_ms += ms_since(start);
    start = thread_cpu_ms();
    HostImage image = rgba_from(rgba.data(), uint32_t(w), uint32_t(h));
    times.to_host_ms += ms_since(start);
    return image;
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

  if (info_.color_format == ColorFormat::mjpg) {
    const AVCodec* codec = avcodec_find_decoder(AV_CODEC_ID_MJPEG);
    if (!codec) throw fail("this FFmpeg has no MJPEG decoder");
    d.jpeg.reset(avcodec_alloc_context3(codec));
    const SensorCut& cut = sensor_cut(info_.color_resolution);
    // A JPEG header claiming more pixels than the track has is refused before anything is allocated.
    av_opt_set_int(d.jpeg.get(), "max_pixels", int64_t(cut.output_width) * cut.output_height, 0);
    d.jpeg->err_recognition = AV_EF_EXPLODE;
    if (const int error = avcodec_open2(d.jpeg.get(), codec, nullptr); error < 0)
      throw fail("cannot open the MJPEG decoder (" + av_error(error) + ")");
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
    capture.color = d.decode_color(*color, info_.color_format, info_.color_resolution,
                                   frame_name("COLOR", *capture.color_device_us), times_);
  }
  return capture;
}

}  // namespace rt::camera::k4a
