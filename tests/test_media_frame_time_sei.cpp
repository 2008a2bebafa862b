// A portrait's RTP time inside its H.264 pictures (media/frame_time_sei.h): stamped by x264's own
// access units, read back as the depayloader hands them on in either stream format; pictures
// without it, other SEI messages and broken bytes give nothing, never a wrong time.
#include <catch2/catch.hpp>

#include <gst/app/gstappsink.h>
#include <gst/gst.h>

#include <cstring>
#include <vector>

#include "media/frame_time_sei.h"

using namespace rt::media;

namespace {

// Access units of x264 at the given stream format, `count` of them, of a moving test picture.
std::vector<GstBuffer*> encoded_pictures(const char* format, int count) {
  if (!gst_is_initialized()) gst_init(nullptr, nullptr);
  const std::string description = "videotestsrc num-buffers=" + std::to_string(count) +
                                  " pattern=ball ! video/x-raw,format=I420,width=96,height=54 ! x264enc tune=zerolatency "
                                  "speed-preset=ultrafast ! video/x-h264,alignment=au,stream-format=" +
                                  format + " ! appsink name=out sync=false";
  GstElement* pipeline = gst_parse_launch(description.c_str(), nullptr);
  REQUIRE(pipeline);
  GstElement* sink = gst_bin_get_by_name(GST_BIN(pipeline), "out");
  gst_element_set_state(pipeline, GST_STATE_PLAYING);
  std::vector<GstBuffer*> out;
  while (GstSample* sample = gst_app_sink_try_pull_sample(GST_APP_SINK(sink), 5 * GST_SECOND)) {
    out.push_back(gst_buffer_ref(gst_sample_get_buffer(sample)));
    gst_sample_unref(sample);
  }
  gst_element_set_state(pipeline, GST_STATE_NULL);
  gst_object_unref(sink);
  gst_object_unref(pipeline);
  return out;
}

// A byte-stream access unit as AVC: each start code replaced by the NAL unit's 4-byte length.
GstBuffer* as_avc(GstBuffer* byte_stream) {
  GstMapInfo map;
  gst_buffer_map(byte_stream, &map, GST_MAP_READ);
  std::vector<size_t> starts;
  for (size_t i = 0; i + 3 <= map.size; ++i)
    if (map.data[i] == 0 && map.data[i + 1] == 0 && map.data[i + 2] == 1) starts.push_back(i + 3);
  std::vector<uint8_t> avc;
  for (size_t k = 0; k < starts.size(); ++k) {
    size_t end = k + 1 < starts.size() ? starts[k + 1] - 3 : map.size;
    while (end > starts[k] && map.data[end - 1] == 0) --end;  // the zero of a four-byte start code
    const uint32_t length = uint32_t(end - starts[k]);
    for (int shift = 24; shift >= 0; shift -= 8) avc.push_back(uint8_t(length >> shift));
    avc.insert(avc.end(), map.data + starts[k], map.data + end);
  }
  gst_buffer_unmap(byte_stream, &map);
  return gst_buffer_new_memdup(avc.data(), avc.size());
}

}  // namespace

TEST_CASE("an access unit carries its RTP time through either stream format", "[media][sei]") {
  const std::vector<GstBuffer*> pictures = encoded_pictures("byte-stream", 6);
  REQUIRE(pictures.size() == 6);
  const uint32_t times[] = {0u, 1u, 90000u, 0x7fffffffu, 0xfffffffeu, 0x00000100u};  // zero bytes need emulation prevention
  for (size_t i = 0; i < pictures.size(); ++i) {
    CHECK_FALSE(frame_time_of(pictures[i], 0).has_value());
    GstBuffer* stamped = with_frame_time(pictures[i], times[i]);
    REQUIRE(stamped);
    CHECK(gst_buffer_get_size(stamped) > gst_buffer_get_size(pictures[i]));
    CHECK(GST_BUFFER_PTS(stamped) == GST_BUFFER_PTS(pictures[i]));
    CHECK(frame_time_of(stamped, 0) == times[i]);
    GstBuffer* avc = as_avc(stamped);
    CHECK(frame_time_of(avc, 4) == times[i]);
    // Read as the wrong format, it yields nothing rather than a wrong time.
    CHECK_FALSE(frame_time_of(avc, 0).has_value());
    CHECK_FALSE(frame_time_of(avc, 7).has_value());
    gst_buffer_unref(avc);
    gst_buffer_unref(stamped);
  }
  for (GstBuffer* b : pictures) gst_buffer_unref(b);
}

TEST_CASE("broken bytes or another's SEI: no time, nothing read out of bounds", "[media][sei]") {
  if (!gst_is_initialized()) gst_init(nullptr, nullptr);
  // Only a parameter set: no time in it, and one stamped in is read back.
  const uint8_t sps_only[] = {0, 0, 0, 1, 0x67, 0x42, 0xc0, 0x1e, 0xda};
  GstBuffer* no_slice = gst_buffer_new_memdup(sps_only, sizeof sps_only);
  CHECK_FALSE(frame_time_of(no_slice, 0).has_value());
  GstBuffer* stamped_alone = with_frame_time(no_slice, 5);
  REQUIRE(stamped_alone);
  CHECK(frame_time_of(stamped_alone, 0) == 5u);
  gst_buffer_unref(stamped_alone);
  gst_buffer_unref(no_slice);
  // An SEI of registered user data from another (country code 0xB5): passed over.
  const uint8_t other_sei[] = {0, 0, 0, 1, 0x06, 0x04, 0x09, 0xb5, 0x00, 0x31, 'G', 'A', '9', '4', 1, 2, 3, 0x80,
                               0, 0, 0, 1, 0x65, 0x88, 0x84, 0x00};
  GstBuffer* other = gst_buffer_new_memdup(other_sei, sizeof other_sei);
  CHECK_FALSE(frame_time_of(other, 0).has_value());
  gst_buffer_unref(other);
  // Random bytes and truncations of a stamped picture.
  std::vector<GstBuffer*> pictures = encoded_pictures("byte-stream", 1);
  REQUIRE(pictures.size() == 1);
  GstBuffer* stamped = with_frame_time(pictures[0], 1234);
  REQUIRE(stamped);
  GstMapInfo map;
  gst_buffer_map(stamped, &map, GST_MAP_READ);
  const std::vector<uint8_t> bytes(map.data, map.data + map.size);
  gst_buffer_unmap(stamped, &map);
  for (size_t cut = 1; cut < 40 && cut < bytes.size(); ++cut) {
    GstBuffer* part = gst_buffer_new_memdup(bytes.data(), cut);
    const auto time = frame_time_of(part, 0);
    CHECK((!time || *time == 1234));
    gst_buffer_unref(part);
  }
  uint32_t state = 12345;
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<uint8_t> noise(1 + trial % 97);
    for (uint8_t& b : noise) b = uint8_t((state = state * 1103515245u + 12345u) >> 16);
    GstBuffer* junk = gst_buffer_new_memdup(noise.data(), noise.size());
    const auto a = frame_time_of(junk, 0), b = frame_time_of(junk, 4);
    CHECK((!a || !b || a == b));  // no crash is the point; a match by chance is astronomically rare
    gst_buffer_unref(junk);
  }
  gst_buffer_unref(stamped);
  gst_buffer_unref(pictures[0]);
}
