#include "camera/k4a_recording_writer.h"

#include <ebml/EbmlHead.h>
#include <ebml/EbmlSubHead.h>
#include <ebml/EbmlVoid.h>
#include <ebml/StdIOCallback.h>
#include <matroska/KaxAttached.h>
#include <matroska/KaxAttachments.h>
#include <matroska/KaxBlock.h>
#include <matroska/KaxCluster.h>
#include <matroska/KaxClusterData.h>
#include <matroska/KaxCues.h>
#include <matroska/KaxCuesData.h>
#include <matroska/KaxInfo.h>
#include <matroska/KaxInfoData.h>
#include <matroska/KaxSeekHead.h>
#include <matroska/KaxSegment.h>
#include <matroska/KaxSemantic.h>
#include <matroska/KaxTag.h>
#include <matroska/KaxTags.h>
#include <matroska/KaxTrackEntryData.h>
#include <matroska/KaxTrackVideo.h>
#include <matroska/KaxTracks.h>
#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

namespace rt::camera::k4a {

using namespace libebml;
using namespace libmatroska;

namespace {

// Block timecodes in microseconds, as the SDK writes them.
constexpr uint64_t kTimecodeScaleNs = 1000;
// Room kept after the EBML header for what is only known at the end.
constexpr uint64_t kSeekHeadRoom = 1024;
constexpr uint64_t kInfoRoom = 256;

// The bytes of a BITMAPINFOHEADER (little-endian fields, 40 bytes): what Video for Windows
// codecs in Matroska carry as CodecPrivate, and where the SDK's playback finds the FourCC.
std::vector<uint8_t> bitmap_info_header(uint32_t width, uint32_t height, uint16_t bit_count, uint32_t fourcc,
                                        uint32_t image_size) {
  std::vector<uint8_t> header(40, 0);
  const auto put32 = [&](size_t at, uint32_t v) {
    for (int i = 0; i < 4; ++i) header[at + i] = uint8_t(v >> (8 * i));
  };
  put32(0, 40);  // biSize
  put32(4, width);
  put32(8, height);
  header[12] = 1;  // biPlanes
  header[14] = uint8_t(bit_count);
  header[15] = uint8_t(bit_count >> 8);
  put32(16, fourcc);  // biCompression
  put32(20, image_size);
  return header;
}

// Bytes of one raw colour frame; 0 for MJPG, whose frames vary.
uint32_t raw_color_bytes(ColorFormat format, const SensorCut& cut) {
  const uint32_t pixels = cut.output_width * cut.output_height;
  switch (format) {
    case ColorFormat::mjpg:
      return 0;
    case ColorFormat::nv12:
      return pixels * 3 / 2;  // 4:2:0
    case ColorFormat::yuy2:
      return pixels * 2;  // 4:2:2
    case ColorFormat::bgra:
      return pixels * 4;
  }
  throw std::invalid_argument("k4a: unknown colour format");
}

std::vector<uint8_t> color_codec_private(ColorFormat format, const SensorCut& cut) {
  const uint16_t bits[] = {24, 12, 16, 32};  // per pixel, in ColorFormat's order
  return bitmap_info_header(cut.output_width, cut.output_height, bits[int(format)], color_fourcc(format),
                            raw_color_bytes(format, cut));
}

// Matroska UIDs: random (so that tracks stay told apart across files), non-zero, distinct
// within the file.
class UidSource {
 public:
  UidSource() : random_(std::random_device{}()) {}
  uint64_t next() {
    uint64_t uid = 0;
    while (uid == 0 || std::find(given_.begin(), given_.end(), uid) != given_.end()) uid = random_() >> 4;
    given_.push_back(uid);
    return uid;
  }

 private:
  std::mt19937_64 random_;
  std::vector<uint64_t> given_;
};

uint8_t to_byte(float value) { return uint8_t(std::lround(std::clamp(value, 0.0f, 1.0f) * 255.0f)); }

void require_rgba8(const HostImage& rgba) {
  if (rgba.format != PixelFormat::RGBA8 && rgba.format != PixelFormat::RGBA32F)
    throw std::invalid_argument(std::string("k4a colour: expected an RGBA image, got ") + format_name(rgba.format));
}

KaxTrackEntry& add_video_track(KaxTracks& tracks, uint64_t number, uint64_t uid, const char* name,
                               const std::vector<uint8_t>& codec_private, const SensorCut& cut, uint64_t period_ns) {
  auto& track = AddNewChild<KaxTrackEntry>(tracks);
  track.SetGlobalTimecodeScale(kTimecodeScaleNs);
  GetChild<KaxTrackNumber>(track).SetValue(number);
  GetChild<KaxTrackUID>(track).SetValue(uid);
  GetChild<KaxTrackType>(track).SetValue(track_video);
  GetChild<KaxTrackName>(track).SetValueUTF8(name);
  GetChild<KaxCodecID>(track).SetValue("V_MS/VFW/FOURCC");
  GetChild<KaxCodecPrivate>(track).CopyBuffer(codec_private.data(), uint32(codec_private.size()));
  GetChild<KaxTrackDefaultDuration>(track).SetValue(period_ns);
  auto& video = GetChild<KaxTrackVideo>(track);
  GetChild<KaxVideoPixelWidth>(video).SetValue(cut.output_width);
  GetChild<KaxVideoPixelHeight>(video).SetValue(cut.output_height);
  track.EnableLacing(false);
  return track;
}

void add_attachment(KaxAttachments& attachments, const char* name, const std::string& bytes, uint64_t uid) {
  auto& attached = AddNewChild<KaxAttached>(attachments);
  GetChild<KaxFileName>(attached).SetValueUTF8(name);
  GetChild<KaxMimeType>(attached).SetValue("application/octet-stream");
  GetChild<KaxFileUID>(attached).SetValue(uid);
  GetChild<KaxFileData>(attached).CopyBuffer(reinterpret_cast<const binary*>(bytes.data()), uint32(bytes.size()));
}

enum class TagTarget { none, track, attachment };

void add_tag(KaxTags& tags, const std::string& name, const std::string& value, TagTarget target = TagTarget::none,
             uint64_t uid = 0) {
  auto& tag = AddNewChild<KaxTag>(tags);
  auto& targets = GetChild<KaxTagTargets>(tag);
  if (target == TagTarget::track) {
    GetChild<KaxTagTargetType>(targets).SetValue("TRACK");
    GetChild<KaxTagTrackUID>(targets).SetValue(uid);
  } else if (target == TagTarget::attachment) {
    GetChild<KaxTagTargetType>(targets).SetValue("ATTACHMENT");
    GetChild<KaxTagAttachmentUID>(targets).SetValue(uid);
  } else {
    // Targets is mandatory: an empty one would not be written at all.
    GetChild<KaxTagTrackUID>(targets).SetValue(0);
  }
  auto& simple = GetChild<KaxTagSimple>(tag);
  GetChild<KaxTagName>(simple).SetValueUTF8(name);
  GetChild<KaxTagString>(simple).SetValueUTF8(value);
}

}  // namespace

std::string_view wired_sync_mode_name(WiredSyncMode mode) {
  switch (mode) {
    case WiredSyncMode::standalone:
      return "STANDALONE";
    case WiredSyncMode::master:
      return "MASTER";
    case WiredSyncMode::subordinate:
      return "SUBORDINATE";
  }
  return "STANDALONE";
}

std::vector<uint8_t> encode_mjpg(const HostImage& rgba, int quality) {
  require_rgba8(rgba);
  if (quality < 1 || quality > 100) throw std::invalid_argument("k4a MJPG: quality must be in [1, 100]");
  cv::Mat bgr(int(rgba.height), int(rgba.width), CV_8UC3);
  for (uint32_t y = 0; y < rgba.height; ++y)
    for (uint32_t x = 0; x < rgba.width; ++x)
      bgr.at<cv::Vec3b>(int(y), int(x)) = {to_byte(rgba.at(x, y, 2)), to_byte(rgba.at(x, y, 1)),
                                           to_byte(rgba.at(x, y, 0))};
  std::vector<uint8_t> jpeg;
  if (!cv::imencode(".jpg", bgr, jpeg, {cv::IMWRITE_JPEG_QUALITY, quality}))
    throw std::runtime_error("k4a MJPG: the JPEG encoder failed");
  return jpeg;
}

std::vector<uint8_t> encode_bgra(const HostImage& rgba) {
  require_rgba8(rgba);
  std::vector<uint8_t> out(size_t(rgba.width) * rgba.height * 4);
  for (uint32_t y = 0; y < rgba.height; ++y)
    for (uint32_t x = 0; x < rgba.width; ++x) {
      uint8_t* px = &out[(size_t(y) * rgba.width + x) * 4];
      px[0] = to_byte(rgba.at(x, y, 2));
      px[1] = to_byte(rgba.at(x, y, 1));
      px[2] = to_byte(rgba.at(x, y, 0));
      px[3] = to_byte(rgba.at(x, y, 3));
    }
  return out;
}

struct RecordingWriter::Matroska {
  explicit Matroska(const std::filesystem::path& path) : io(path.c_str(), MODE_CREATE) {}
  StdIOCallback io;
  KaxSegment segment;
  KaxTrackEntry* color = nullptr;
  KaxTrackEntry* depth = nullptr;
  EbmlVoid seek_room, info_room;
  KaxCues cues;
  UidSource uids;
  uint64_t start_offset_ns = 0;
  uint64_t last_timecode_ns = 0;
};

RecordingWriter::RecordingWriter(const std::filesystem::path& path, RecordingConfig config)
    : path_(path), config_(std::move(config)) {
  if (!is_frame_rate(config_.fps))
    throw std::invalid_argument("k4a recording: " + std::to_string(config_.fps) + " fps is not a k4a rate (5, 15, 30)");
  try {
    file_ = std::make_unique<Matroska>(path);
  } catch (const std::exception& e) {
    throw std::runtime_error("k4a recording: cannot create '" + path.string() + "': " + e.what());
  }
}

RecordingWriter::~RecordingWriter() {
  try {
    close();
  } catch (...) {
    // A destructor must not throw; close() explicitly to see the error.
  }
}

void RecordingWriter::write_header(uint64_t start_offset_ns) {
  Matroska& m = *file_;
  m.start_offset_ns = start_offset_ns;
  KaxSegment& segment = m.segment;

  EbmlHead head;
  GetChild<EDocType>(head).SetValue("matroska");
  GetChild<EDocTypeVersion>(head).SetValue(2);
  GetChild<EDocTypeReadVersion>(head).SetValue(2);
  head.Render(m.io, true);
  // An 8-byte size field, rewritten at the end once the size is known.
  segment.WriteHead(m.io, 8);
  m.seek_room.SetSize(kSeekHeadRoom);
  m.seek_room.Render(m.io);
  m.info_room.SetSize(kInfoRoom);
  m.info_room.Render(m.io);

  KaxTracks& tracks = GetChild<KaxTracks>(segment);
  const uint64_t period_ns = frame_period_ns(config_.fps);
  const SensorCut& color_cut = sensor_cut(config_.color_resolution);
  const SensorCut& depth_cut = sensor_cut(config_.depth_mode);
  const uint64_t color_uid = m.uids.next(), depth_uid = m.uids.next(), calibration_uid = m.uids.next();
  m.color = &add_video_track(tracks, 1, color_uid, "COLOR", color_codec_private(config_.color_format, color_cut),
                             color_cut, period_ns);
  m.depth = &add_video_track(tracks, 2, depth_uid, "DEPTH",
                             bitmap_info_header(depth_cut.output_width, depth_cut.output_height, 16, kDepthFourcc,
                                                depth_cut.output_width * depth_cut.output_height * 2),
                             depth_cut, period_ns);
  tracks.Render(m.io);

  KaxAttachments& attachments = GetChild<KaxAttachments>(segment);
  add_attachment(attachments, "calibration.json", write_calibration_json(config_.calibration), calibration_uid);
  attachments.Render(m.io);

  KaxTags& tags = GetChild<KaxTags>(segment);
  add_tag(tags, "K4A_COLOR_TRACK", std::to_string(color_uid), TagTarget::track, color_uid);
  add_tag(tags, "K4A_COLOR_MODE", color_mode_tag(config_.color_format, config_.color_resolution), TagTarget::track,
          color_uid);
  add_tag(tags, "K4A_DEPTH_TRACK", std::to_string(depth_uid), TagTarget::track, depth_uid);
  add_tag(tags, "K4A_DEPTH_MODE", std::string(depth_mode_name(config_.depth_mode)), TagTarget::track, depth_uid);
  add_tag(tags, "K4A_DEPTH_DELAY_NS", std::to_string(config_.depth_delay_ns));
  add_tag(tags, "K4A_WIRED_SYNC_MODE", std::string(wired_sync_mode_name(config_.wired_sync)));
  if (config_.wired_sync == WiredSyncMode::subordinate)
    add_tag(tags, "K4A_SUBORDINATE_DELAY_NS", std::to_string(config_.subordinate_delay_ns));
  add_tag(tags, "K4A_START_OFFSET_NS", std::to_string(start_offset_ns));
  if (!config_.serial.empty()) add_tag(tags, "K4A_DEVICE_SERIAL_NUMBER", config_.serial);
  add_tag(tags, "K4A_CALIBRATION_FILE", "calibration.json", TagTarget::attachment, calibration_uid);
  tags.Render(m.io);
}

void RecordingWriter::write_capture(uint64_t color_device_time_us, std::span<const uint8_t> color,
                                    const HostImage& depth_mm) {
  if (closed_) throw std::logic_error("k4a recording: write after close");
  const bool has_color = !color.empty(), has_depth = depth_mm.width > 0 || depth_mm.height > 0;
  if (!has_color && !has_depth) throw std::invalid_argument("k4a recording: a capture without colour or depth");
  const SensorCut& depth_cut = sensor_cut(config_.depth_mode);
  if (has_depth && (depth_mm.format != PixelFormat::R16U || depth_mm.width != depth_cut.output_width ||
                    depth_mm.height != depth_cut.output_height))
    throw std::invalid_argument(std::string("k4a recording: depth must be ") + format_name(PixelFormat::R16U) + " " +
                                std::to_string(depth_cut.output_width) + "x" + std::to_string(depth_cut.output_height) +
                                " (" + std::string(depth_mode_name(config_.depth_mode)) + "), got " +
                                format_name(depth_mm.format) + " " + std::to_string(depth_mm.width) + "x" +
                                std::to_string(depth_mm.height));
  const size_t raw_size = raw_color_bytes(config_.color_format, sensor_cut(config_.color_resolution));
  if (has_color && raw_size != 0 && color.size() != raw_size)
    throw std::invalid_argument("k4a recording: " + std::string(color_format_name(config_.color_format)) +
                                " colour of " + std::to_string(color.size()) + " bytes, the mode needs " +
                                std::to_string(raw_size));
  const int64_t depth_time_signed = int64_t(color_device_time_us) + config_.depth_delay_ns / 1000;
  if (has_depth && depth_time_signed < 0)
    throw std::invalid_argument("k4a recording: depth time before the device's zero");
  const uint64_t depth_time_us = uint64_t(std::max<int64_t>(0, depth_time_signed));
  const uint64_t first_us = !has_depth   ? color_device_time_us
                            : !has_color ? depth_time_us
                                         : std::min(color_device_time_us, depth_time_us);
  const uint64_t last_us = !has_depth   ? color_device_time_us
                           : !has_color ? depth_time_us
                                        : std::max(color_device_time_us, depth_time_us);
  if (captures_ > 0 && first_us <= last_time_us_)
    throw std::invalid_argument("k4a recording: capture times must increase (" + std::to_string(first_us) +
                                " us after " + std::to_string(last_time_us_) + " us)");
  Matroska& m = *file_;
  if (captures_ == 0) write_header(first_us * 1000);
  last_time_us_ = last_us;

  // Depth is stored big-endian ("b16g").
  std::vector<uint8_t> depth_bytes(depth_mm.texels.size() * 2);
  for (size_t i = 0; i < depth_mm.texels.size(); ++i) {
    const uint16_t v = uint16_t(std::clamp(depth_mm.texels[i], 0.0f, 65535.0f));
    depth_bytes[2 * i] = uint8_t(v >> 8);
    depth_bytes[2 * i + 1] = uint8_t(v);
  }

  // One cluster per capture: its timecode is the earlier of the two images.
  KaxCluster cluster;
  cluster.SetParent(m.segment);
  const uint64_t cluster_ns = first_us * 1000 - m.start_offset_ns;
  cluster.InitTimecode(cluster_ns / kTimecodeScaleNs, kTimecodeScaleNs);
  GetChild<KaxClusterTimecode>(cluster);
  struct Frame {
    KaxTrackEntry* track;
    uint64_t time_ns;
    const uint8_t* data;
    size_t size;
  };
  std::vector<Frame> frames;
  if (has_color)
    frames.push_back({m.color, color_device_time_us * 1000 - m.start_offset_ns, color.data(), color.size()});
  if (has_depth)
    frames.push_back({m.depth, depth_time_us * 1000 - m.start_offset_ns, depth_bytes.data(), depth_bytes.size()});
  std::sort(frames.begin(), frames.end(), [](const Frame& a, const Frame& b) { return a.time_ns < b.time_ns; });
  for (const Frame& frame : frames) {
    auto& block = AddNewChild<KaxSimpleBlock>(cluster);
    block.SetParent(cluster);
    // The block owns the buffer (it copies the bytes and frees them when the cluster goes).
    auto* buffer = new DataBuffer(const_cast<binary*>(frame.data), uint32(frame.size), nullptr, true);
    block.AddFrame(*frame.track, frame.time_ns, *buffer, LACING_NONE);
    block.SetKeyframe(true);
  }
  cluster.Render(m.io, m.cues);

  // An index entry a second, as the SDK keeps it, at the cluster's first block.
  const uint64_t cue_gap_ns = 1'000'000'000ull;
  if (captures_ == 0 || cluster_ns >= m.last_timecode_ns + cue_gap_ns) {
    auto& point = AddNewChild<KaxCuePoint>(m.cues);
    GetChild<KaxCueTime>(point).SetValue(cluster_ns / kTimecodeScaleNs);
    auto& positions = GetChild<KaxCueTrackPositions>(point);
    GetChild<KaxCueTrack>(positions).SetValue(GetChild<KaxTrackNumber>(*frames.front().track).GetValue());
    GetChild<KaxCueClusterPosition>(positions).SetValue(m.segment.GetRelativePosition(cluster));
    m.last_timecode_ns = cluster_ns;
  }
  ++captures_;
}

void RecordingWriter::close() {
  if (closed_) return;
  closed_ = true;
  Matroska& m = *file_;
  if (captures_ == 0) write_header(0);
  KaxSegment& segment = m.segment;

  KaxInfo& info = GetChild<KaxInfo>(segment);
  GetChild<KaxTimecodeScale>(info).SetValue(kTimecodeScaleNs);
  GetChild<KaxMuxingApp>(info).SetValue(L"libmatroska");
  GetChild<KaxWritingApp>(info).SetValueUTF8("remotetouch");
  const double duration_units =
      captures_ == 0 ? 0.0 : double((last_time_us_ * 1000 - m.start_offset_ns) / kTimecodeScaleNs);
  GetChild<KaxDuration>(info).SetValue(duration_units);
  m.info_room.ReplaceWith(info, m.io);

  if (m.cues.ListSize() > 0) m.cues.Render(m.io);

  KaxSeekHead& seek = GetChild<KaxSeekHead>(segment);
  seek.IndexThis(info, segment);
  seek.IndexThis(GetChild<KaxTracks>(segment), segment);
  seek.IndexThis(GetChild<KaxAttachments>(segment), segment);
  seek.IndexThis(GetChild<KaxTags>(segment), segment);
  if (m.cues.ListSize() > 0) seek.IndexThis(m.cues, segment);
  m.seek_room.ReplaceWith(seek, m.io);

  m.io.setFilePointer(0, seek_end);
  const uint64_t segment_size = m.io.getFilePointer() - segment.GetElementPosition() - segment.HeadSize();
  segment.SetSizeInfinite(true);
  segment.ForceSize(segment_size);
  segment.OverwriteHead(m.io);
  m.io.close();
}

}  // namespace rt::camera::k4a
