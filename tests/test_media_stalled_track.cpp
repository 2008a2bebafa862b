// media::StalledTrack: a track whose packets keep coming while no picture comes out asks for a
// keyframe after two whole pictures, again only after its pause, and not while pictures come out.
#include <catch2/catch.hpp>

#include "media/stalled_track.h"

using rt::media::StalledTrack;

namespace {
// Packets of one picture (three, one timestamp), 33 ms apart per picture; true if any asked.
bool stalled_picture_in(StalledTrack& track, uint32_t picture, uint64_t now_us) {
  bool asked = false;
  for (int packet = 0; packet < 3; ++packet) asked |= track.on_packet(picture * 3000, now_us);
  return asked;
}
}  // namespace

TEST_CASE("a track whose pictures stop coming out asks for a keyframe, paced", "[media][stalled]") {
  StalledTrack track(2, 500'000);
  uint64_t now = 1'000'000;
  // Pictures coming out after each: never asks.
  for (uint32_t p = 0; p < 10; ++p, now += 33'000) {
    CHECK_FALSE(stalled_picture_in(track, p, now));
    track.on_picture();
  }
  // Nothing out from picture 10 on: pictures 10 and 11 go in whole, the first packet of 12 asks.
  CHECK_FALSE(stalled_picture_in(track, 10, now));
  now += 33'000;
  CHECK_FALSE(stalled_picture_in(track, 11, now));
  now += 33'000;
  CHECK(track.on_packet(12 * 3000, now));
  CHECK_FALSE(track.on_packet(12 * 3000, now));  // the rest of the same picture does not ask again
  // Still stalled: not again within half a second, then again.
  uint32_t p = 13;
  int asked = 0;
  for (const uint64_t until = now + 499'000; now + 33'000 < until; ++p) {
    now += 33'000;
    asked += stalled_picture_in(track, p, now) ? 1 : 0;
  }
  CHECK(asked == 0);
  now += 40'000;
  CHECK(stalled_picture_in(track, p++, now));
  // A picture comes out: the count starts over, two more whole pictures before asking.
  track.on_picture();
  now += 600'000;
  CHECK_FALSE(stalled_picture_in(track, p++, now));
  CHECK_FALSE(stalled_picture_in(track, p++, now));
  CHECK(stalled_picture_in(track, p++, now));
}

TEST_CASE("a track that never showed a picture asks too: its first packets were lost", "[media][stalled]") {
  StalledTrack track;
  CHECK_FALSE(track.on_packet(100, 0));
  CHECK_FALSE(track.on_packet(3100, 33'000));
  CHECK(track.on_packet(6100, 66'000));
}
