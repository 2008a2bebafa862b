#pragma once
// What a WebRTC call (direct or through Janus) shares before it is up: touch events, numbered in
// the order the site made them and held (a bounded few: touches are a few a second, a call that
// never opens holds no more) until the reliable channel takes them, in order; and the blank first
// picture whose caps let webrtcbin make the offer (it goes before the call is up, so it is dropped).
#include <cstdint>
#include <deque>
#include <functional>
#include <mutex>

#include "net/messages.h"

namespace rt::media {

class PendingTouches {
 public:
  static constexpr size_t kCapacity = 64;
  // Numbers it (from 1); beyond capacity the oldest is dropped and counted.
  void add(net::TouchEventMessage touch);
  // Sends the waiting touches in order while `send` takes them; returns how many went.
  size_t flush(const std::function<bool(const net::TouchEventMessage&)>& send);
  // The other site left: the waiting touches are dropped and counted (returned). A touch is a
  // contact of this moment; one delivered to the site that comes back seconds later would pulse
  // its motor for a contact that is over.
  size_t drop_all();
  uint64_t dropped() const;

 private:
  mutable std::mutex mutex_;
  std::deque<net::TouchEventMessage> waiting_;
  uint64_t sequence_ = 0, dropped_ = 0;
};

net::PortraitMessage blank_portrait(uint32_t width, uint32_t height);

}  // namespace rt::media
