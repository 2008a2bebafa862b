#pragma once
// A portrait's RTP time carried inside its own H.264 pictures, as an SEI message in front of the
// picture's first slice. The RTP header's timestamp is what pairs a portrait's colour and depth
// pictures with its frame record, but an SFU may rewrite it: Janus's VideoRoom starts each
// subscriber's streams at zero from whichever packet it relays first, so the two tracks' times
// no longer match each other or the record. Nothing on the way touches the bitstream itself.
//
// The message is "registered user data" (ITU-T T.35, country code 0xFF, extension 0xFF) holding
// the tag "RTft" and the time, big-endian: GStreamer 1.22's codec parsers write that kind, not the
// unregistered one. The encoders here give Annex B byte streams (start codes); rtph264depay hands
// on either that or AVC (each NAL unit after its length), as the decoder asks.
#include <cstdint>
#include <optional>

typedef struct _GstBuffer GstBuffer;
typedef struct _GstH264NalParser GstH264NalParser;

namespace rt::media {

// One stream's writer or reader of the time. It keeps its NAL parser, which is a quarter of a
// megabyte, zeroed when made: a stream's pictures reuse one rather than make one each. Use it
// from one thread at a time (a pad probe's streaming thread).
class FrameTimeSei {
 public:
  FrameTimeSei();
  ~FrameTimeSei();
  FrameTimeSei(const FrameTimeSei&) = delete;
  FrameTimeSei& operator=(const FrameTimeSei&) = delete;

  // A new access unit with the time in front of its first slice (at its end if it has none);
  // nullptr if GStreamer could not make or insert the message. `au` is left as it was.
  GstBuffer* with_frame_time(GstBuffer* au, uint32_t rtp_time);

  // The time an access unit carries, if it carries one of ours; malformed NAL units and other SEI
  // messages are passed over. `nal_length_size`: 0 for a byte stream, else AVC's length size (1..4).
  std::optional<uint32_t> frame_time_of(GstBuffer* au, unsigned nal_length_size);

 private:
  GstH264NalParser* parser_;
};

// The same, with a parser of their own, for a picture now and then.
GstBuffer* with_frame_time(GstBuffer* au, uint32_t rtp_time);
std::optional<uint32_t> frame_time_of(GstBuffer* au, unsigned nal_length_size);

}  // namespace rt::media
