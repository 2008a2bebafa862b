#include "media/codec_probes.h"

#include <gst/video/video.h>

#include <algorithm>
#include <vector>

#include "time/monotonic_clock.h"

namespace rt::media {

void CodecClock::attach(GstElement* element) {
  GstPad* sink = gst_element_get_static_pad(element, "sink");
  GstPad* src = gst_element_get_static_pad(element, "src");
  if (sink)
    gst_pad_add_probe(sink, GST_PAD_PROBE_TYPE_BUFFER, +[](GstPad*, GstPadProbeInfo* info, gpointer d) {
                        static_cast<CodecClock*>(d)->entered(GST_BUFFER_PTS(GST_PAD_PROBE_INFO_BUFFER(info)));
                        return GST_PAD_PROBE_OK;
                      },
                      this, nullptr);
  if (src)
    gst_pad_add_probe(src, GstPadProbeType(GST_PAD_PROBE_TYPE_BUFFER | GST_PAD_PROBE_TYPE_BUFFER_LIST),
                      +[](GstPad*, GstPadProbeInfo* info, gpointer d) {
                        GstBuffer* buffer = (info->type & GST_PAD_PROBE_TYPE_BUFFER_LIST)
                                                ? gst_buffer_list_get(GST_PAD_PROBE_INFO_BUFFER_LIST(info), 0)
                                                : GST_PAD_PROBE_INFO_BUFFER(info);
                        if (buffer) static_cast<CodecClock*>(d)->left(GST_BUFFER_PTS(buffer));
                        return GST_PAD_PROBE_OK;
                      },
                      this, nullptr);
  if (sink) gst_object_unref(sink);
  if (src) gst_object_unref(src);
}

void CodecClock::entered(GstClockTime pts) {
  std::lock_guard lock(mutex_);
  pending_[next_pending_++ % kPending] = {pts, monotonic_now_us()};
}

void CodecClock::left(GstClockTime pts) {
  const uint64_t now = monotonic_now_us();
  std::lock_guard lock(mutex_);
  // A picture leaving in several buffers counts once, at its first.
  if (count_ > 0 && pts == last_left_pts_) return;
  last_left_pts_ = pts;
  // A decoder keeps the presentation time; an encoder moves it (GstVideoEncoder shifts it far
  // ahead, so that decoding times stay positive) but keeps the order (no B-frames), so the oldest
  // picture still inside is the one leaving.
  std::pair<GstClockTime, uint64_t>* match = nullptr;
  for (auto& entry : pending_)
    if (entry.second && entry.first == pts) match = &entry;
  if (!match)
    for (auto& entry : pending_)
      if (entry.second && (!match || entry.second < match->second)) match = &entry;
  if (!match) return;
  samples_[count_++ % kSamples] = float(double(now - match->second) * 1e-3);
  match->second = 0;
}

double CodecClock::percentile_ms(double q) const {
  std::vector<float> values;
  {
    std::lock_guard lock(mutex_);
    values.assign(samples_.begin(), samples_.begin() + std::min<uint64_t>(count_, kSamples));
  }
  if (values.empty()) return 0.0;
  const size_t at = std::min(values.size() - 1, size_t(q * double(values.size())));
  std::nth_element(values.begin(), values.begin() + long(at), values.end());
  return values[at];
}

double CodecClock::median_ms() const { return percentile_ms(0.5); }
double CodecClock::p90_ms() const { return percentile_ms(0.9); }
uint64_t CodecClock::pictures() const {
  std::lock_guard lock(mutex_);
  return count_;
}

void KeyframeRequests::attach(GstPad* pad) {
  gst_pad_add_probe(pad, GST_PAD_PROBE_TYPE_EVENT_UPSTREAM, +[](GstPad*, GstPadProbeInfo* info, gpointer d) {
                      if (gst_video_event_is_force_key_unit(GST_PAD_PROBE_INFO_EVENT(info))) {
                        auto* self = static_cast<KeyframeRequests*>(d);
                        std::lock_guard lock(self->mutex_);
                        ++self->count_;
                      }
                      return GST_PAD_PROBE_OK;
                    },
                    this, nullptr);
}

uint64_t KeyframeRequests::count() const {
  std::lock_guard lock(mutex_);
  return count_;
}

}  // namespace rt::media
