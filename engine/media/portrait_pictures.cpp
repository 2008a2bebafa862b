#include "media/portrait_pictures.h"

#include <gst/app/gstappsrc.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

namespace rt::media {
namespace {

GstBuffer* new_picture(GstVideoFormat format, uint32_t width, uint32_t height, GstVideoInfo& info, GstVideoFrame& frame) {
  gst_video_info_set_format(&info, format, width, height);
  GstBuffer* buffer = gst_buffer_new_allocate(nullptr, GST_VIDEO_INFO_SIZE(&info), nullptr);
  if (!buffer || !gst_video_frame_map(&frame, &info, buffer, GST_MAP_WRITE)) {
    if (buffer) gst_buffer_unref(buffer);
    throw std::runtime_error("a video picture of " + std::to_string(width) + "x" + std::to_string(height) + " could not be made");
  }
  return buffer;
}

}  // namespace

GstBuffer* make_color_picture(const HostImage& color, uint32_t width, uint32_t height) {
  const uint32_t w = color.width, h = color.height;
  // Straight-alpha RGB to 8 bits.
  cv::Mat rgb(int(h), int(w), CV_8UC3);
  uint8_t* out = rgb.ptr<uint8_t>();
  for (size_t i = 0, n = size_t(w) * h; i < n; ++i)
    for (size_t c = 0; c < 3; ++c) {
      const float v = color.texels[i * 4 + c];
      // Not lround: 2.8 million calls a 720p portrait. NaN (which clamp passes through) is 0.
      out[i * 3 + c] = uint8_t(std::clamp(std::isfinite(v) ? v : 0.0f, 0.0f, 1.0f) * 255.0f + 0.5f);
    }
  if (width != w || height != h) {
    cv::Mat smaller;
    cv::resize(rgb, smaller, cv::Size(int(width), int(height)), 0, 0, cv::INTER_AREA);
    rgb = smaller;
  }
  cv::Mat yuv;
  cv::cvtColor(rgb, yuv, cv::COLOR_RGB2YUV_I420);
  GstVideoInfo info;
  GstVideoFrame frame;
  GstBuffer* buffer = new_picture(GST_VIDEO_FORMAT_I420, width, height, info, frame);
  const uint8_t* in = yuv.ptr<uint8_t>();
  for (int plane = 0; plane < 3; ++plane) {
    const uint32_t pw = plane ? width / 2 : width, ph = plane ? height / 2 : height;
    auto* plane_out = static_cast<uint8_t*>(GST_VIDEO_FRAME_PLANE_DATA(&frame, plane));
    const int stride = GST_VIDEO_FRAME_PLANE_STRIDE(&frame, plane);
    for (uint32_t y = 0; y < ph; ++y, in += pw) std::copy_n(in, pw, plane_out + size_t(y) * size_t(stride));
  }
  gst_video_frame_unmap(&frame);
  return buffer;
}

GstBuffer* make_depth_alpha_picture(const HostImage& color, const HostImage& depth, const DepthRange& range,
                                    uint32_t width, uint32_t height) {
  GstVideoInfo info;
  GstVideoFrame frame;
  GstBuffer* buffer = new_picture(GST_VIDEO_FORMAT_Y444_10LE, width, height, info, frame);
  const auto plane = [&](int index) {
    const size_t stride = size_t(GST_VIDEO_FRAME_PLANE_STRIDE(&frame, index)) / 2;
    return std::pair(std::span(static_cast<uint16_t*>(GST_VIDEO_FRAME_PLANE_DATA(&frame, index)), stride * height), stride);
  };
  const auto [luma, luma_stride] = plane(0);
  const auto [alpha, alpha_stride] = plane(1);
  const auto [neutral, neutral_stride] = plane(2);
  // Coded at the portrait's size first, so that each code sampled is one pixel's own.
  const size_t pixels = size_t(color.width) * color.height;
  std::vector<uint16_t> luma_codes(pixels), alpha_codes(pixels);
  encode_depth_alpha_plane(color, depth, range, luma_codes, alpha_codes, color.width);
  if (pixels > kSoftEdgeMaxPixels) std::fill(alpha_codes.begin(), alpha_codes.end(), uint16_t(0));
  if (width != color.width || height != color.height) {
    luma_codes = resample_codes_nearest(luma_codes, color.width, color.height, width, height);
    alpha_codes = resample_codes_nearest(alpha_codes, color.width, color.height, width, height);
  }
  for (uint32_t y = 0; y < height; ++y) {
    std::copy_n(luma_codes.data() + size_t(y) * width, width, luma.data() + y * luma_stride);
    std::copy_n(alpha_codes.data() + size_t(y) * width, width, alpha.data() + y * alpha_stride);
    std::fill_n(neutral.data() + y * neutral_stride, width, kNeutralChromaCode);
  }
  gst_video_frame_unmap(&frame);
  return buffer;
}

void set_picture_size(GstElement* appsrc, uint32_t width, uint32_t height) {
  GstCaps* caps = gst_app_src_get_caps(GST_APP_SRC(appsrc));
  if (!caps) throw std::runtime_error("an appsrc without caps cannot change its picture size");
  caps = gst_caps_make_writable(caps);
  gst_caps_set_simple(caps, "width", G_TYPE_INT, int(width), "height", G_TYPE_INT, int(height), nullptr);
  gst_app_src_set_caps(GST_APP_SRC(appsrc), caps);
  gst_caps_unref(caps);
}


std::vector<uint8_t> rgb_of_color_picture(const GstVideoFrame& frame, uint32_t call_width, uint32_t call_height) {
  const uint32_t w = GST_VIDEO_FRAME_WIDTH(&frame), h = GST_VIDEO_FRAME_HEIGHT(&frame);
  // Gather the three planes into OpenCV's contiguous I420 layout, then to RGB.
  cv::Mat yuv(int(h * 3 / 2), int(w), CV_8UC1);
  uint8_t* out = yuv.ptr<uint8_t>();
  for (int plane = 0; plane < 3; ++plane) {
    const uint32_t pw = plane ? w / 2 : w, ph = plane ? h / 2 : h;
    const auto* in = static_cast<const uint8_t*>(GST_VIDEO_FRAME_PLANE_DATA(&frame, plane));
    const int stride = GST_VIDEO_FRAME_PLANE_STRIDE(&frame, plane);
    for (uint32_t y = 0; y < ph; ++y, out += pw) std::copy_n(in + size_t(y) * size_t(stride), pw, out);
  }
  std::vector<uint8_t> rgb(size_t(call_width) * call_height * 3);
  cv::Mat rgb_mat(int(call_height), int(call_width), CV_8UC3, rgb.data());
  if (w == call_width && h == call_height) {
    cv::cvtColor(yuv, rgb_mat, cv::COLOR_YUV2RGB_I420);
  } else {
    cv::Mat smaller;
    cv::cvtColor(yuv, smaller, cv::COLOR_YUV2RGB_I420);
    cv::resize(smaller, rgb_mat, rgb_mat.size(), 0, 0, cv::INTER_LINEAR);
  }
  return rgb;
}

DepthAlphaCodes codes_of_depth_alpha_picture(const GstVideoFrame& frame, uint32_t call_width, uint32_t call_height) {
  const uint32_t w = GST_VIDEO_FRAME_WIDTH(&frame), h = GST_VIDEO_FRAME_HEIGHT(&frame);
  const auto plane = [&](int index) {
    std::vector<uint16_t> codes(size_t(w) * h);
    const auto* in = static_cast<const uint8_t*>(GST_VIDEO_FRAME_PLANE_DATA(&frame, index));
    const int stride = GST_VIDEO_FRAME_PLANE_STRIDE(&frame, index);
    for (uint32_t y = 0; y < h; ++y) std::memcpy(codes.data() + size_t(y) * w, in + size_t(y) * size_t(stride), w * 2);
    if (w == call_width && h == call_height) return codes;
    return resample_codes_nearest(codes, w, h, call_width, call_height);
  };
  return {plane(0), plane(1)};
}

}  // namespace rt::media
