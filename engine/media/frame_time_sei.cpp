#include "media/frame_time_sei.h"

#include <gst/codecparsers/gsth264parser.h>
#include <gst/gst.h>

#include <array>
#include <memory>

namespace rt::media {
namespace {

constexpr std::array<uint8_t, 4> kTag = {'R', 'T', 'f', 't'};
constexpr uint8_t kCountry = 0xFF, kCountryExtension = 0xFF;

}  // namespace

FrameTimeSei::FrameTimeSei() : parser_(gst_h264_nal_parser_new()) {}

FrameTimeSei::~FrameTimeSei() { gst_h264_nal_parser_free(parser_); }

GstBuffer* FrameTimeSei::with_frame_time(GstBuffer* au, uint32_t rtp_time) {
  std::array<uint8_t, 8> payload = {kTag[0], kTag[1], kTag[2], kTag[3], uint8_t(rtp_time >> 24), uint8_t(rtp_time >> 16),
                                    uint8_t(rtp_time >> 8), uint8_t(rtp_time)};
  GstH264SEIMessage message{};
  message.payloadType = GST_H264_SEI_REGISTERED_USER_DATA;
  message.payload.registered_user_data.country_code = kCountry;
  message.payload.registered_user_data.country_code_extension = kCountryExtension;
  message.payload.registered_user_data.data = payload.data();
  message.payload.registered_user_data.size = guint(payload.size());
  GArray* messages = g_array_new(FALSE, FALSE, sizeof(GstH264SEIMessage));
  g_array_append_val(messages, message);
  GstMemory* sei = gst_h264_create_sei_memory(4, messages);
  g_array_unref(messages);
  if (!sei) return nullptr;
  GstBuffer* out = gst_h264_parser_insert_sei(parser_, au, sei);
  gst_memory_unref(sei);
  if (out) gst_buffer_copy_into(out, au, GstBufferCopyFlags(GST_BUFFER_COPY_FLAGS | GST_BUFFER_COPY_TIMESTAMPS | GST_BUFFER_COPY_META), 0, -1);
  return out;
}

std::optional<uint32_t> FrameTimeSei::frame_time_of(GstBuffer* au, unsigned nal_length_size) {
  if (nal_length_size > 4) return std::nullopt;
  GstMapInfo map;
  if (!gst_buffer_map(au, &map, GST_MAP_READ)) return std::nullopt;
  std::optional<uint32_t> found;
  GstH264NalUnit nalu{};
  guint offset = 0;
  while (!found && offset < map.size) {
    const GstH264ParserResult r =
        nal_length_size ? gst_h264_parser_identify_nalu_avc(parser_, map.data, offset, map.size, guint8(nal_length_size), &nalu)
                        : gst_h264_parser_identify_nalu(parser_, map.data, offset, guint(map.size), &nalu);
    if (r != GST_H264_PARSER_OK && r != GST_H264_PARSER_NO_NAL_END) break;
    if (nalu.type == GST_H264_NAL_SEI) {
      GArray* messages = nullptr;
      if (gst_h264_parser_parse_sei(parser_, &nalu, &messages) == GST_H264_PARSER_OK && messages) {
        for (guint i = 0; i < messages->len && !found; ++i) {
          const GstH264SEIMessage& m = g_array_index(messages, GstH264SEIMessage, i);
          if (m.payloadType != GST_H264_SEI_REGISTERED_USER_DATA) continue;
          const GstH264RegisteredUserData& data = m.payload.registered_user_data;
          if (data.country_code != kCountry || data.country_code_extension != kCountryExtension || data.size != 8) continue;
          if (!std::equal(kTag.begin(), kTag.end(), data.data)) continue;
          found = uint32_t(data.data[4]) << 24 | uint32_t(data.data[5]) << 16 | uint32_t(data.data[6]) << 8 | data.data[7];
        }
      }
      if (messages) g_array_unref(messages);
    }
    if (r == GST_H264_PARSER_NO_NAL_END) break;
    offset = nalu.offset + nalu.size;
  }
  gst_buffer_unmap(au, &map);
  return found;
}

GstBuffer* with_frame_time(GstBuffer* au, uint32_t rtp_time) { return FrameTimeSei().with_frame_time(au, rtp_time); }

std::optional<uint32_t> frame_time_of(GstBuffer* au, unsigned nal_length_size) {
  return FrameTimeSei().frame_time_of(au, nal_length_size);
}

}  // namespace rt::media
