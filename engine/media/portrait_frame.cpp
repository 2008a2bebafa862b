#include "media/portrait_frame.h"

#include <cmath>
#include <cstring>

#include "net/byte_io.h"

namespace rt::media {

bool is_portrait_frame(std::span<const uint8_t> bytes) {
  return bytes.size() >= 4 && std::memcmp(bytes.data(), kPortraitFrameMagic, 4) == 0;
}

std::vector<uint8_t> encode_portrait_frame(const PortraitFrame& frame) {
  std::vector<uint8_t> bytes;
  bytes.reserve(kPortraitFrameSize);
  net::ByteWriter w(bytes);
  w.put_bytes(kPortraitFrameMagic);
  w.put<uint16_t>(kPortraitFrameVersion);
  w.put<uint16_t>(0);
  w.put<uint32_t>(frame.rtp_timestamp);
  w.put<uint64_t>(frame.frame_index);
  w.put<uint64_t>(frame.capture_timestamp_us);
  w.put<uint32_t>(frame.width);
  w.put<uint32_t>(frame.height);
  for (double v : {frame.fx, frame.fy, frame.cx, frame.cy}) w.put<double>(v);
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) w.put<double>(frame.camera_from_site(r, c));
  w.put<double>(frame.depth_range.near_m);
  w.put<double>(frame.depth_range.far_m);
  return bytes;
}

std::optional<PortraitFrame> decode_portrait_frame(std::span<const uint8_t> bytes, uint32_t width, uint32_t height,
                                                   std::string* error) {
  auto fail = [&](std::string why) -> std::optional<PortraitFrame> {
    if (error) *error = "portrait frame record: " + why;
    return std::nullopt;
  };
  if (bytes.size() != kPortraitFrameSize)
    return fail(std::to_string(bytes.size()) + " bytes, expected " + std::to_string(kPortraitFrameSize));
  if (!is_portrait_frame(bytes)) return fail("bad magic");
  // The size was checked above: every read below is within the record.
  net::ByteReader r(bytes.subspan(4));
  const uint16_t version = r.get<uint16_t>();
  if (version != kPortraitFrameVersion)
    return fail("version " + std::to_string(version) + ", this build reads " + std::to_string(kPortraitFrameVersion));
  if (r.get<uint16_t>() != 0) return fail("the reserved field is not 0");
  PortraitFrame f;
  f.rtp_timestamp = r.get<uint32_t>();
  f.frame_index = r.get<uint64_t>();
  f.capture_timestamp_us = r.get<uint64_t>();
  f.width = r.get<uint32_t>();
  f.height = r.get<uint32_t>();
  if (f.width != width || f.height != height)
    return fail("size " + std::to_string(f.width) + "x" + std::to_string(f.height) + ", the link carries " +
                std::to_string(width) + "x" + std::to_string(height));
  f.fx = r.get<double>();
  f.fy = r.get<double>();
  f.cx = r.get<double>();
  f.cy = r.get<double>();
  for (int row = 0; row < 4; ++row)
    for (int c = 0; c < 4; ++c) f.camera_from_site(row, c) = r.get<double>();
  f.depth_range.near_m = r.get<double>();
  f.depth_range.far_m = r.get<double>();
  if (!std::isfinite(f.fx) || !std::isfinite(f.fy) || !std::isfinite(f.cx) || !std::isfinite(f.cy) || f.fx <= 0 ||
      f.fy <= 0 || !f.camera_from_site.allFinite())
    return fail("the camera is not finite or has a focal length <= 0");
  if (const std::string why = check_depth_range(f.depth_range); !why.empty()) return fail(why);
  return f;
}

net::PortraitMessage portrait_of_planes(const PortraitFrame& f, std::span<const uint8_t> rgb,
                                        const DepthAlphaCodes& codes) {
  net::PortraitMessage p;
  p.frame_index = f.frame_index;
  p.capture_timestamp_us = f.capture_timestamp_us;
  p.width = f.width;
  p.height = f.height;
  p.fx = f.fx;
  p.fy = f.fy;
  p.cx = f.cx;
  p.cy = f.cy;
  p.camera_from_site = f.camera_from_site;
  p.color = HostImage(f.width, f.height, PixelFormat::RGBA32F);
  p.depth = HostImage(f.width, f.height, PixelFormat::R32F);
  for (size_t i = 0, n = size_t(f.width) * f.height; i < n; ++i)
    for (size_t c = 0; c < 3; ++c) p.color.texels[i * 4 + c] = float(rgb[i * 3 + c]) * (1.0f / 255.0f);
  decode_depth_alpha_plane(codes.luma, codes.alpha, f.width, f.depth_range, p.color, p.depth);
  return p;
}

}  // namespace rt::media
