#pragma once
// When a receiving track should ask for a keyframe although no packet was seen missing. A CPU module.
#include <cstdint>
#include <mutex>

namespace rt::media {

// A track whose pictures stopped coming out while its packets still arrive: the depayloader is
// dropping them until a keyframe, and no gap told it to ask for one (the first packets of a call
// lost, or a keyframe request of its lost too). Given each packet's RTP timestamp and each picture
// that came out, it says when to ask for a keyframe: after `pictures` whole pictures went in (a
// newer timestamp began each time) with nothing out, then again each `again_us` while it lasts.
class StalledTrack {
 public:
  explicit StalledTrack(int pictures = 2, uint64_t again_us = 500'000) : pictures_(pictures), again_us_(again_us) {}
  bool on_packet(uint32_t rtp_timestamp, uint64_t now_us);  // true: ask for a keyframe now
  void on_picture();

 private:
  const int pictures_;
  const uint64_t again_us_;
  mutable std::mutex mutex_;
  bool have_timestamp_ = false, asked_ = false;
  uint32_t timestamp_ = 0;
  uint64_t pictures_out_ = 0, pictures_out_at_last_timestamp_ = 0, last_asked_us_ = 0;
  int pictures_in_without_out_ = 0;
};

}  // namespace rt::media
