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
  GstBuffer* buffer = new_picture(GST_VIDEO_FORMAT_I420_10LE, width, height, info, frame);
  const size_t luma_stride = size_t(GST_VIDEO_FRAME_PLANE_STRIDE(&frame, 0)) / 2;
  const std::span luma(static_cast<uint16_t*>(GST_VIDEO_FRAME_PLANE_DATA(&frame, 0)), luma_stride * height);
  if (width == color.width && height == color.height) {
    encode_depth_alpha_plane(color, depth, range, luma, luma_stride);
  } else {
    // Coded at the portrait's size first, so that each code sampled is one pixel's own.
    std::vector<uint16_t> codes(size_t(color.width) * color.height);
    encode_depth_alpha_plane(color, depth, range, codes, color.width);
    const std::vector<uint16_t> smaller = resample_codes_nearest(codes, color.width, color.height, width, height);
    for (uint32_t y = 0; y < height; ++y) std::copy_n(smaller.data() + size_t(y) * width, width, luma.data() + y * luma_stride);
  }
  for (int plane = 1; plane < 3; ++plane) {
    auto* out = static_cast<uint8_t*>(GST_VIDEO_FRAME_PLANE_DATA(&frame, plane));
    const size_t stride = size_t(GST_VIDEO_FRAME_PLANE_STRIDE(&frame, plane));
    for (uint32_t y = 0; y < height / 2; ++y) std::fill_n(reinterpret_cast<uint16_t*>(out + y * stride), width / 2, uint16_t(512));
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

std::vector<uint16_t> codes_of_depth_alpha_picture(const GstVideoFrame& frame, uint32_t call_width, uint32_t call_height) {
  const uint32_t w = GST_VIDEO_FRAME_WIDTH(&frame), h = GST_VIDEO_FRAME_HEIGHT(&frame);
  std::vector<uint16_t> codes(size_t(w) * h);
  const auto* in = static_cast<const uint8_t*>(GST_VIDEO_FRAME_PLANE_DATA(&frame, 0));
  const int stride = GST_VIDEO_FRAME_PLANE_STRIDE(&frame, 0);
  for (uint32_t y = 0; y < h; ++y) std::memcpy(codes.data() + size_t(y) * w, in + size_t(y) * size_t(stride), w * 2);
  if (w == call_width && h == call_height) return codes;
  return resample_codes_nearest(codes, w, h, call_width, call_height);
}


}  // namespace rt::media
