// A fake libk4a.so.1.4 for the tests: each k4a recording named in REMOTETOUCH_FAKE_K4A_RECORDINGS
// (paths separated by ':') is one connected device, which serves the recording's captures
// through the k4a C API as the device gave them: its serial number, its factory calibration
// (the calibration.json attachment), MJPG / raw colour bytes, depth as little-endian DEPTH16 and
// each image's device time. The live backend's own code then runs in CI unchanged. It reads the
// file with libavformat on its own, not through the engine's reader that it is compared with.
//
// A device fails its next capture (as an unplugged one does) after its recording's last.
// REMOTETOUCH_FAKE_K4A_FAULT = "N:KIND" spoils capture N of every device: null-buffer,
// wrong-size, wrong-stride, ir-format, huge-size, no-depth. REMOTETOUCH_FAKE_K4A_LOG names a
// file that gets a line per start and stop ("start SERIAL color=0 resolution=1 depth=2 fps=2
// sync=1 delay=0"), so that a test sees the order and the modes the backend asked for.
// REMOTETOUCH_FAKE_K4A_SILENT = SERIAL: that device gives its first capture, then none (each
// call waits its timeout, up to 3 s, and times out), as a subordinate whose sync cable came loose.
// REMOTETOUCH_FAKE_K4A_LOOPS = N: each device serves its recording N times over, its device
// clock running on (each pass a frame period after the last), so that a short recording lasts as
// long as a test needs another device beside it to run.
// REMOTETOUCH_FAKE_K4A_PACED = 1: a device gives a capture no sooner than one frame period after
// its previous one, as a real device's sensor does (a site that runs live is then paced by it).
// fake_k4a_open_handles() counts the captures and images not yet released.
extern "C" {
#include <libavformat/avformat.h>
}

#include <algorithm>
#include <atomic>
#include <chrono>
#include <thread>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "camera/k4a_api.h"

namespace {

struct FakeImage {
  std::vector<uint8_t> bytes;
  k4a_image_format_t format = K4A_IMAGE_FORMAT_CUSTOM;
  int width = 0, height = 0, stride = 0;
  uint64_t device_us = 0;
  size_t reported_size = 0;
  bool null_buffer = false;
};

struct FakeCaptureData {
  std::optional<FakeImage> color, depth;
};

struct FakeDevice {
  std::string path, serial, calibration, color_mode, depth_mode;
  int fps = 30;
  std::vector<FakeCaptureData> captures;
  size_t next = 0;
  bool open = false, started = false;
  std::chrono::steady_clock::time_point last_given{};
};

struct FakeCapture {
  FakeCaptureData data;
};

std::vector<std::unique_ptr<FakeDevice>> g_devices;
std::atomic<int> g_open_handles{0};

std::string tag(const AVFormatContext* format, const char* name) {
  const auto search = [&](const AVDictionary* dictionary) -> std::string {
    const AVDictionaryEntry* entry = nullptr;
    while ((entry = av_dict_get(dictionary, "", entry, AV_DICT_IGNORE_SUFFIX))) {
      const std::string key = entry->key;
      if (key == name || (key.size() > std::strlen(name) && key.ends_with(std::string("/") + name))) return entry->value;
    }
    return "";
  };
  std::string value = search(format->metadata);
  for (unsigned i = 0; value.empty() && i < format->nb_streams; ++i) value = search(format->streams[i]->metadata);
  return value;
}

int mode_width(const std::string& name, bool color, int* height) {
  struct Mode { const char* name; int w, h; };
  static const Mode kColor[] = {{"720P", 1280, 720}, {"1080P", 1920, 1080}, {"1440P", 2560, 1440},
                                {"1536P", 2048, 1536}, {"2160P", 3840, 2160}, {"3072P", 4096, 3072}};
  static const Mode kDepth[] = {{"NFOV_2X2BINNED", 320, 288}, {"NFOV_UNBINNED", 640, 576},
                                {"WFOV_2X2BINNED", 512, 512}, {"WFOV_UNBINNED", 1024, 1024}};
  for (const Mode& mode : color ? std::span<const Mode>(kColor) : std::span<const Mode>(kDepth))
    if (name.ends_with(mode.name)) return *height = mode.h, mode.w;
  return *height = 0, 0;
}

k4a_image_format_t color_format_of(const std::string& color_mode) {
  if (color_mode.starts_with("MJPG")) return K4A_IMAGE_FORMAT_COLOR_MJPG;
  if (color_mode.starts_with("NV12")) return K4A_IMAGE_FORMAT_COLOR_NV12;
  if (color_mode.starts_with("YUY2")) return K4A_IMAGE_FORMAT_COLOR_YUY2;
  return K4A_IMAGE_FORMAT_COLOR_BGRA32;
}

// Reads the whole recording (the tests' recordings are a few captures); false when it cannot.
bool load(FakeDevice& device) {
  AVFormatContext* format = nullptr;
  av_log_set_level(AV_LOG_FATAL);  // a device says nothing on its own; the backend reports
  if (avformat_open_input(&format, device.path.c_str(), nullptr, nullptr) < 0) return false;
  int color_stream = -1, depth_stream = -1;
  for (unsigned i = 0; i < format->nb_streams; ++i) {
    const AVStream* stream = format->streams[i];
    const AVDictionaryEntry* title = av_dict_get(stream->metadata, "title", nullptr, 0);
    if (stream->codecpar->codec_type == AVMEDIA_TYPE_VIDEO && title) {
      if (std::strcmp(title->value, "COLOR") == 0) color_stream = int(i);
      if (std::strcmp(title->value, "DEPTH") == 0) depth_stream = int(i);
    }
    if (stream->codecpar->codec_type == AVMEDIA_TYPE_ATTACHMENT && stream->codecpar->extradata)
      device.calibration.assign(reinterpret_cast<const char*>(stream->codecpar->extradata),
                                size_t(stream->codecpar->extradata_size));
  }
  device.serial = tag(format, "K4A_DEVICE_SERIAL_NUMBER");
  device.color_mode = tag(format, "K4A_COLOR_MODE");
  device.depth_mode = tag(format, "K4A_DEPTH_MODE");
  const uint64_t start_us = std::strtoull(tag(format, "K4A_START_OFFSET_NS").c_str(), nullptr, 10) / 1000;
  const int64_t depth_delay_us = std::strtoll(tag(format, "K4A_DEPTH_DELAY_NS").c_str(), nullptr, 10) / 1000;
  const AVRational rate = format->streams[color_stream < 0 ? 0 : color_stream]->avg_frame_rate;
  device.fps = rate.den > 0 ? int(0.5 + double(rate.num) / rate.den) : 30;
  const int64_t half_period_us = 500'000 / device.fps;
  int color_height = 0, depth_height = 0;
  const int color_width = mode_width(device.color_mode, true, &color_height);
  const int depth_width = mode_width(device.depth_mode, false, &depth_height);
  const k4a_image_format_t color_format = color_format_of(device.color_mode);
  const int color_bpp = color_format == K4A_IMAGE_FORMAT_COLOR_BGRA32 ? 4 : color_format == K4A_IMAGE_FORMAT_COLOR_YUY2 ? 2 : 1;

  AVPacket* packet = av_packet_alloc();
  FakeCaptureData current;
  while (av_read_frame(format, packet) >= 0) {
    const bool is_color = packet->stream_index == color_stream, is_depth = packet->stream_index == depth_stream;
    if (!is_color && !is_depth) {
      av_packet_unref(packet);
      continue;
    }
    const AVStream* stream = format->streams[packet->stream_index];
    FakeImage image;
    image.device_us = uint64_t(av_rescale_q(packet->pts, stream->time_base, AVRational{1, 1000000})) + start_us;
    if (is_color) {
      image.bytes.assign(packet->data, packet->data + packet->size);
      image.format = color_format;
      image.width = color_width, image.height = color_height;
      image.stride = color_format == K4A_IMAGE_FORMAT_COLOR_MJPG ? 0 : color_width * color_bpp;
    } else {
      image.bytes.resize(size_t(packet->size));
      for (int i = 0; i + 1 < packet->size; i += 2) {  // b16g is big-endian; DEPTH16 is the machine's order
        image.bytes[size_t(i)] = packet->data[i + 1];
        image.bytes[size_t(i) + 1] = packet->data[i];
      }
      image.format = K4A_IMAGE_FORMAT_DEPTH16;
      image.width = depth_width, image.height = depth_height, image.stride = depth_width * 2;
    }
    image.reported_size = image.bytes.size();
    av_packet_unref(packet);
    std::optional<FakeImage>& slot = is_color ? current.color : current.depth;
    const std::optional<FakeImage>& other = is_color ? current.depth : current.color;
    bool belongs = !slot;
    if (belongs && other) {
      const int64_t color_us = int64_t(is_color ? image.device_us : other->device_us);
      const int64_t depth_us = int64_t(is_color ? other->device_us : image.device_us) - depth_delay_us;
      belongs = std::llabs(depth_us - color_us) < half_period_us;
    }
    if (!belongs) {
      device.captures.push_back(std::move(current));
      current = FakeCaptureData{};
    }
    (is_color ? current.color : current.depth) = std::move(image);
  }
  if (current.color || current.depth) device.captures.push_back(std::move(current));
  av_packet_free(&packet);
  avformat_close_input(&format);
  return true;
}

void spoil(FakeCaptureData& data, size_t index) {
  const char* fault = std::getenv("REMOTETOUCH_FAKE_K4A_FAULT");
  if (!fault) return;
  char* kind = nullptr;
  const unsigned long n = std::strtoul(fault, &kind, 10);
  if (n != index || !kind || *kind != ':') return;
  const std::string what = kind + 1;
  if (what == "no-depth") data.depth.reset();
  if (!data.color || !data.depth) return;
  if (what == "null-buffer") data.color->null_buffer = true;
  if (what == "wrong-size") data.depth->width += 16;
  if (what == "wrong-stride") data.depth->stride -= 2;
  if (what == "ir-format") data.depth->format = K4A_IMAGE_FORMAT_IR16;
  if (what == "huge-size") data.color->reported_size = size_t(1) << 40;
}

void log_line(const std::string& line) {
  const char* path = std::getenv("REMOTETOUCH_FAKE_K4A_LOG");
  if (!path) return;
  if (std::FILE* file = std::fopen(path, "a")) {
    std::fprintf(file, "%s\n", line.c_str());
    std::fclose(file);
  }
}

FakeDevice* device_of(k4a_device_t handle) { return reinterpret_cast<FakeDevice*>(handle); }

k4a_buffer_result_t copy_out(const std::string& text, uint8_t* data, size_t* size, bool terminate) {
  if (!size) return K4A_BUFFER_RESULT_FAILED;
  const size_t needed = text.size() + (terminate ? 1 : 0);
  if (!data || *size < needed) {
    *size = needed;
    return K4A_BUFFER_RESULT_TOO_SMALL;
  }
  std::memcpy(data, text.data(), text.size());
  if (terminate) data[text.size()] = 0;
  *size = needed;
  return K4A_BUFFER_RESULT_SUCCEEDED;
}

}  // namespace

extern "C" {

__attribute__((visibility("default"))) int fake_k4a_open_handles() { return g_open_handles.load(); }

__attribute__((visibility("default"))) uint32_t k4a_device_get_installed_count() {
  // The recordings are read again while no device is open, so that a test can change them
  // between cases; an open device must stay where its handle points.
  for (const auto& device : g_devices)
    if (device->open) return uint32_t(g_devices.size());
  g_devices.clear();
  const char* list = std::getenv("REMOTETOUCH_FAKE_K4A_RECORDINGS");
  std::string rest = list ? list : "";
  while (!rest.empty()) {
    const size_t colon = rest.find(':');
    auto device = std::make_unique<FakeDevice>();
    device->path = rest.substr(0, colon);
    rest = colon == std::string::npos ? "" : rest.substr(colon + 1);
    if (!device->path.empty()) g_devices.push_back(std::move(device));
  }
  return uint32_t(g_devices.size());
}

__attribute__((visibility("default"))) k4a_result_t k4a_device_open(uint32_t index, k4a_device_t* handle) {
  if (!handle || index >= g_devices.size() || g_devices[index]->open) return K4A_RESULT_FAILED;
  FakeDevice& device = *g_devices[index];
  if (device.captures.empty() && !load(device)) return K4A_RESULT_FAILED;
  device.open = true;
  device.next = 0;
  *handle = reinterpret_cast<k4a_device_t>(&device);
  return K4A_RESULT_SUCCEEDED;
}

__attribute__((visibility("default"))) k4a_buffer_result_t k4a_device_get_serialnum(k4a_device_t handle, char* serial,
                                                                                   size_t* size) {
  return copy_out(device_of(handle)->serial, reinterpret_cast<uint8_t*>(serial), size, true);
}

__attribute__((visibility("default"))) k4a_buffer_result_t k4a_device_get_raw_calibration(k4a_device_t handle,
                                                                                         uint8_t* data, size_t* size) {
  return copy_out(device_of(handle)->calibration, data, size, true);
}

__attribute__((visibility("default"))) k4a_result_t k4a_device_start_cameras(k4a_device_t handle,
                                                                             const k4a_device_configuration_t* config) {
  FakeDevice& device = *device_of(handle);
  log_line("start " + device.serial + " color=" + std::to_string(config->color_format) +
           " resolution=" + std::to_string(config->color_resolution) + " depth=" + std::to_string(config->depth_mode) +
           " fps=" + std::to_string(config->camera_fps) + " sync=" + std::to_string(config->wired_sync_mode) +
           " delay=" + std::to_string(config->subordinate_delay_off_master_usec) +
           " synchronized=" + std::to_string(config->synchronized_images_only));
  // The device runs only in the modes it recorded.
  static const char* kResolutions[] = {"OFF", "720P", "1080P", "1440P", "1536P", "2160P", "3072P"};
  static const char* kDepthModes[] = {"OFF", "NFOV_2X2BINNED", "NFOV_UNBINNED", "WFOV_2X2BINNED", "WFOV_UNBINNED"};
  static const int kFps[] = {5, 15, 30};
  if (device.started || config->color_format != color_format_of(device.color_mode) || config->color_resolution < 1 ||
      config->color_resolution > 6 || !device.color_mode.ends_with(kResolutions[config->color_resolution]) ||
      config->depth_mode < 1 || config->depth_mode > 4 || device.depth_mode != kDepthModes[config->depth_mode] ||
      config->camera_fps > 2 || kFps[config->camera_fps] != device.fps)
    return K4A_RESULT_FAILED;
  device.started = true;
  return K4A_RESULT_SUCCEEDED;
}

__attribute__((visibility("default"))) k4a_wait_result_t k4a_device_get_capture(k4a_device_t handle,
                                                                                k4a_capture_t* capture, int32_t timeout_ms) {
  FakeDevice& device = *device_of(handle);
  const char* loops = std::getenv("REMOTETOUCH_FAKE_K4A_LOOPS");
  const size_t passes = loops ? size_t(std::clamp(std::atoi(loops), 1, 1000)) : 1;
  if (!device.started || device.captures.empty() || device.next >= device.captures.size() * passes)
    return K4A_WAIT_RESULT_FAILED;
  const char* silent = std::getenv("REMOTETOUCH_FAKE_K4A_SILENT");
  if (silent && device.serial == silent && device.next > 0) {
    std::this_thread::sleep_for(std::chrono::milliseconds(std::clamp(timeout_ms, 0, 3000)));
    return K4A_WAIT_RESULT_TIMEOUT;
  }
  const char* paced = std::getenv("REMOTETOUCH_FAKE_K4A_PACED");
  if (paced && std::strcmp(paced, "1") == 0 && device.next > 0) {
    const auto due = device.last_given + std::chrono::microseconds(1'000'000 / std::max(device.fps, 1));
    if (timeout_ms >= 0 && due - std::chrono::steady_clock::now() > std::chrono::milliseconds(timeout_ms)) {
      std::this_thread::sleep_for(std::chrono::milliseconds(timeout_ms));
      return K4A_WAIT_RESULT_TIMEOUT;
    }
    std::this_thread::sleep_until(due);
  }
  device.last_given = std::chrono::steady_clock::now();
  auto* fake = new FakeCapture{device.captures[device.next % device.captures.size()]};
  if (const size_t pass = device.next / device.captures.size(); pass > 0) {
    // One span for every device, so that devices in wired sync stay together pass after pass.
    uint64_t first_us = UINT64_MAX, last_us = 0;
    for (const auto& each : g_devices)
      for (const FakeCaptureData& data : each->captures)
        for (const std::optional<FakeImage>& image : {data.color, data.depth})
          if (image) first_us = std::min(first_us, image->device_us), last_us = std::max(last_us, image->device_us);
    const uint64_t span_us = last_us - first_us + 1'000'000 / uint64_t(std::max(device.fps, 1));
    for (std::optional<FakeImage>* image : {&fake->data.color, &fake->data.depth})
      if (*image) (*image)->device_us += pass * span_us;
  }
  spoil(fake->data, device.next);
  ++device.next;
  ++g_open_handles;
  *capture = reinterpret_cast<k4a_capture_t>(fake);
  return K4A_WAIT_RESULT_SUCCEEDED;
}

static k4a_image_t lend(const std::optional<FakeImage>& image) {
  if (!image) return nullptr;
  ++g_open_handles;
  return reinterpret_cast<k4a_image_t>(new FakeImage(*image));
}

__attribute__((visibility("default"))) k4a_image_t k4a_capture_get_color_image(k4a_capture_t capture) {
  return lend(reinterpret_cast<FakeCapture*>(capture)->data.color);
}
__attribute__((visibility("default"))) k4a_image_t k4a_capture_get_depth_image(k4a_capture_t capture) {
  return lend(reinterpret_cast<FakeCapture*>(capture)->data.depth);
}

static FakeImage& image_of(k4a_image_t image) { return *reinterpret_cast<FakeImage*>(image); }

__attribute__((visibility("default"))) uint8_t* k4a_image_get_buffer(k4a_image_t image) {
  return image_of(image).null_buffer ? nullptr : image_of(image).bytes.data();
}
__attribute__((visibility("default"))) size_t k4a_image_get_size(k4a_image_t image) { return image_of(image).reported_size; }
__attribute__((visibility("default"))) int k4a_image_get_width_pixels(k4a_image_t image) { return image_of(image).width; }
__attribute__((visibility("default"))) int k4a_image_get_height_pixels(k4a_image_t image) { return image_of(image).height; }
__attribute__((visibility("default"))) int k4a_image_get_stride_bytes(k4a_image_t image) { return image_of(image).stride; }
__attribute__((visibility("default"))) uint64_t k4a_image_get_device_timestamp_usec(k4a_image_t image) {
  return image_of(image).device_us;
}
__attribute__((visibility("default"))) k4a_image_format_t k4a_image_get_format(k4a_image_t image) {
  return image_of(image).format;
}
__attribute__((visibility("default"))) void k4a_image_release(k4a_image_t image) {
  --g_open_handles;
  delete &image_of(image);
}
__attribute__((visibility("default"))) void k4a_capture_release(k4a_capture_t capture) {
  --g_open_handles;
  delete reinterpret_cast<FakeCapture*>(capture);
}
__attribute__((visibility("default"))) void k4a_device_stop_cameras(k4a_device_t handle) {
  FakeDevice& device = *device_of(handle);
  if (device.started) log_line("stop " + device.serial);
  device.started = false;
}
__attribute__((visibility("default"))) void k4a_device_close(k4a_device_t handle) {
  FakeDevice& device = *device_of(handle);
  device.open = false;
  device.started = false;
}

}  // extern "C"
