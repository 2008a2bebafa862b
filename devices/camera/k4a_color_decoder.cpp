#include "camera/k4a_color_decoder.h"

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavutil/opt.h>
#include <libswscale/swscale.h>
}

#include <array>
#include <cstring>
#include <ctime>
#include <vector>

namespace rt::camera::k4a {

namespace {

std::string decoder_error_text(int code) {
  char text[AV_ERROR_MAX_STRING_SIZE] = {};
  av_strerror(code, text, sizeof(text));
  return text;
}

HostImage host_rgba_from(const uint8_t* pixels, uint32_t width, uint32_t height) {
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

double cpu_ms_since(double start_ms) { return thread_cpu_ms() - start_ms; }

}  // namespace

double thread_cpu_ms() {
  timespec now{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
  return double(now.tv_sec) * 1e3 + double(now.tv_nsec) * 1e-6;
}

std::string color_size_problem(ColorFormat format, ColorResolution resolution, size_t size, const std::string& frame_name) {
  const SensorCut& cut = sensor_cut(resolution);
  const size_t w = cut.output_width, h = cut.output_height;
  const std::string mode = std::string(color_format_name(format)) + " " + std::to_string(w) + "x" + std::to_string(h);
  if (size == 0) return frame_name + " has no bytes";
  size_t expected = 0;
  switch (format) {
    case ColorFormat::mjpg:
      // No JPEG of a mode is larger than its raw BGRA image; a larger one is not a frame.
      if (size > w * h * 4)
        return frame_name + " has " + std::to_string(size) + " bytes, more than a " + mode + " frame can have";
      return "";
    case ColorFormat::nv12: expected = w * h * 3 / 2; break;
    case ColorFormat::yuy2: expected = w * h * 2; break;
    case ColorFormat::bgra: expected = w * h * 4; break;
  }
  if (size != expected)
    return frame_name + " has " + std::to_string(size) + " bytes, " + mode + " needs " + std::to_string(expected) +
           " (truncated or damaged)";
  return "";
}

struct ColorDecoder::Codec {
  AVCodecContext* jpeg = nullptr;
  AVFrame* frame = av_frame_alloc();
  AVPacket* packet = av_packet_alloc();
  SwsContext* scaler = nullptr;
  std::vector<uint8_t> padded;  // the JPEG with the zero padding libavcodec reads past its end
  std::vector<uint8_t> rgba;
  ~Codec() {
    sws_freeContext(scaler);
    av_packet_free(&packet);
    av_frame_free(&frame);
    avcodec_free_context(&jpeg);
  }
};

ColorDecoder::ColorDecoder(ColorFormat format, ColorResolution resolution)
    : format_(format), resolution_(resolution), codec_(std::make_unique<Codec>()) {
  if (!codec_->frame || !codec_->packet) throw ImageError("out of memory for a colour decoder");
  if (format != ColorFormat::mjpg) return;
  const AVCodec* codec = avcodec_find_decoder(AV_CODEC_ID_MJPEG);
  if (!codec) throw ImageError("this FFmpeg has no MJPEG decoder");
  codec_->jpeg = avcodec_alloc_context3(codec);
  const SensorCut& cut = sensor_cut(resolution);
  // A JPEG header claiming more pixels than the mode has is refused before anything is allocated.
  av_opt_set_int(codec_->jpeg, "max_pixels", int64_t(cut.output_width) * cut.output_height, 0);
  codec_->jpeg->err_recognition = AV_EF_EXPLODE;
  if (const int error = avcodec_open2(codec_->jpeg, codec, nullptr); error < 0)
    throw ImageError("cannot open the MJPEG decoder (" + decoder_error_text(error) + ")");
}

ColorDecoder::~ColorDecoder() = default;

HostImage ColorDecoder::decode(const uint8_t* data, size_t size, const std::string& frame_name, DecodeTimes& times) {
  Codec& c = *codec_;
  double start = thread_cpu_ms();
  const SensorCut& cut = sensor_cut(resolution_);
  const int w = int(cut.output_width), h = int(cut.output_height);
  if (!data) throw ImageError(frame_name + " has no bytes");
  if (std::string problem = color_size_problem(format_, resolution_, size, frame_name); !problem.empty())
    throw ImageError(problem);
  AVPixelFormat source_format = AV_PIX_FMT_NONE;
  const uint8_t* planes[4] = {};
  int strides[4] = {};
  switch (format_) {
    case ColorFormat::mjpg: {
      c.padded.assign(data, data + size);
      c.padded.resize(size + AV_INPUT_BUFFER_PADDING_SIZE, 0);
      c.packet->data = c.padded.data();
      c.packet->size = int(size);
      int error = avcodec_send_packet(c.jpeg, c.packet);
      if (error >= 0) error = avcodec_receive_frame(c.jpeg, c.frame);
      if (error < 0 || (c.frame->flags & AV_FRAME_FLAG_CORRUPT) || c.frame->decode_error_flags)
        throw ImageError(frame_name + " is not a decodable JPEG (" +
                         (error < 0 ? decoder_error_text(error) : std::string("decode errors")) + ")");
      if (c.frame->width != w || c.frame->height != h)
        throw ImageError(frame_name + " decodes to " + std::to_string(c.frame->width) + "x" +
                         std::to_string(c.frame->height) + ", the mode is " + std::to_string(w) + "x" + std::to_string(h));
      source_format = AVPixelFormat(c.frame->format);
      times.color_decode_ms += cpu_ms_since(start);
      start = thread_cpu_ms();
      for (int i = 0; i < 4; ++i) planes[i] = c.frame->data[i], strides[i] = c.frame->linesize[i];
      break;
    }
    case ColorFormat::nv12:
      source_format = AV_PIX_FMT_NV12;
      planes[0] = data, strides[0] = w;
      planes[1] = data + size_t(w) * h, strides[1] = w;
      break;
    case ColorFormat::yuy2:
      source_format = AV_PIX_FMT_YUYV422;
      planes[0] = data, strides[0] = w * 2;
      break;
    case ColorFormat::bgra:
      source_format = AV_PIX_FMT_BGRA;
      planes[0] = data, strides[0] = w * 4;
      break;
  }
  // Chroma interpolated at full resolution: without it the colour is biased by more than a level.
  // The exactly rounded path would cost about three times as long for a fraction of a level.
  c.scaler = sws_getCachedContext(c.scaler, w, h, source_format, w, h, AV_PIX_FMT_RGBA,
                                  SWS_BILINEAR | SWS_FULL_CHR_H_INT, nullptr, nullptr, nullptr);
  if (!c.scaler) throw ImageError(frame_name + ": no conversion from its pixel format to RGBA");
  c.rgba.resize(size_t(w) * h * 4);
  uint8_t* out[4] = {c.rgba.data(), nullptr, nullptr, nullptr};
  int out_strides[4] = {w * 4, 0, 0, 0};
  sws_scale(c.scaler, planes, strides, 0, h, out, out_strides);
  times.color_convert_ms += cpu_ms_since(start);
  start = thread_cpu_ms();
  HostImage image = host_rgba_from(c.rgba.data(), uint32_t(w), uint32_t(h));
  times.to_host_ms += cpu_ms_since(start);
  return image;
}

}  // namespace rt::camera::k4a
