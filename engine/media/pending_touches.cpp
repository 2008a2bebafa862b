#include "media/pending_touches.h"

namespace rt::media {

void PendingTouches::add(net::TouchEventMessage touch) {
  std::lock_guard lock(mutex_);
  touch.sequence = ++sequence_;
  if (waiting_.size() >= kCapacity) {
    waiting_.pop_front();
    ++dropped_;
  }
  waiting_.push_back(touch);
}

size_t PendingTouches::flush(const std::function<bool(const net::TouchEventMessage&)>& send) {
  std::lock_guard lock(mutex_);  // held while sending: two flushes would otherwise swap two touches
  size_t sent = 0;
  while (!waiting_.empty() && send(waiting_.front())) {
    waiting_.pop_front();
    ++sent;
  }
  return sent;
}

size_t PendingTouches::drop_all() {
  std::lock_guard lock(mutex_);
  const size_t dropped = waiting_.size();
  waiting_.clear();
  dropped_ += dropped;
  return dropped;
}

uint64_t PendingTouches::dropped() const {
  std::lock_guard lock(mutex_);
  return dropped_;
}

net::PortraitMessage blank_portrait(uint32_t width, uint32_t height) {
  net::PortraitMessage p;
  p.width = width;
  p.height = height;
  p.fx = p.fy = double(width);
  p.cx = width / 2.0;
  p.cy = height / 2.0;
  p.color = HostImage(width, height, PixelFormat::RGBA32F);
  p.depth = HostImage(width, height, PixelFormat::R32F);
  return p;
}

}  // namespace rt::media
