#pragma once
// What a portrait's video frames do not carry: its index, capture time, size, the camera it was
// rendered for and the depth range its luma is quantized over. One small record per portrait on
// the unordered data channel, keyed by the RTP timestamp both video tracks carry; the receiver
// pairs the three by that timestamp.
//
//   "RTWP" | version u16 = 1 | reserved u16 = 0 | rtp_timestamp u32 | frame_index u64 |
//   capture_timestamp_us u64 | width u32 | height u32 | fx fy cx cy f64 | camera_from_site 16 x f64
//   (row-major) | depth near, far f64                                                   212 bytes
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "media/depth_alpha_codec.h"
#include "net/messages.h"

namespace rt::media {

inline constexpr uint8_t kPortraitFrameMagic[4] = {'R', 'T', 'W', 'P'};
inline constexpr uint16_t kPortraitFrameVersion = 1;
inline constexpr size_t kPortraitFrameSize = 4 + 2 + 2 + 4 + 8 + 8 + 4 + 4 + 4 * 8 + 16 * 8 + 2 * 8;

struct PortraitFrame {
  uint32_t rtp_timestamp = 0;
  uint64_t frame_index = 0;
  uint64_t capture_timestamp_us = 0;
  uint32_t width = 0, height = 0;
  double fx = 0, fy = 0, cx = 0, cy = 0;
  Eigen::Matrix4d camera_from_site = Eigen::Matrix4d::Identity();
  DepthRange depth_range;
};

std::vector<uint8_t> encode_portrait_frame(const PortraitFrame& frame);
// Untrusted bytes: the exact size, magic, version, finite values, the size the receiver expects
// (`width` x `height`), a usable depth range. Empty with `error` set otherwise.
std::optional<PortraitFrame> decode_portrait_frame(std::span<const uint8_t> bytes, uint32_t width, uint32_t height,
                                                   std::string* error);
bool is_portrait_frame(std::span<const uint8_t> bytes);

// The portrait a record describes, from its two decoded pictures: `rgb` 8-bit colour, `codes` the
// depth/alpha codes (media/depth_alpha_codec.h), each width*height of the record's size.
net::PortraitMessage portrait_of_planes(const PortraitFrame& frame, std::span<const uint8_t> rgb,
                                        const DepthAlphaCodes& codes);

}  // namespace rt::media
