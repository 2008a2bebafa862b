#include "media/stalled_track.h"

namespace rt::media {

bool StalledTrack::on_packet(uint32_t rtp_timestamp, uint64_t now_us) {
  std::lock_guard lock(mutex_);
  if (have_timestamp_ && rtp_timestamp == timestamp_) return false;
  if (have_timestamp_) {
    // The picture of the previous timestamp went in whole (a newer one begins); did any come out?
    pictures_in_without_out_ = pictures_out_ == pictures_out_at_last_timestamp_ ? pictures_in_without_out_ + 1 : 0;
  }
  have_timestamp_ = true;
  timestamp_ = rtp_timestamp;
  pictures_out_at_last_timestamp_ = pictures_out_;
  if (pictures_in_without_out_ < pictures_) return false;
  if (asked_ && now_us < last_asked_us_ + again_us_) return false;
  asked_ = true;
  last_asked_us_ = now_us;
  return true;
}

void StalledTrack::on_picture() {
  std::lock_guard lock(mutex_);
  ++pictures_out_;
  pictures_in_without_out_ = 0;
}

}  // namespace rt::media
