#include "net/connection_rate_limit.h"

#include <algorithm>
#include <stdexcept>

namespace rt::net {

std::string address_key(const asio::ip::address& address) {
  if (address.is_v4()) {
    const auto bytes = address.to_v4().to_bytes();
    return std::string(bytes.begin(), bytes.end());
  }
  const auto v6 = address.to_v6();
  if (v6.is_v4_mapped()) return address_key(asio::ip::make_address_v4(asio::ip::v4_mapped, v6));
  const auto bytes = v6.to_bytes();
  return std::string(bytes.begin(), bytes.end());
}

std::string prefix_key(const std::string& address_key) { return address_key.substr(0, address_key.size() == 4 ? 3 : 8); }

ConnectionRateLimit::ConnectionRateLimit(uint32_t per_second, uint32_t burst, size_t max_addresses)
    : per_second_(per_second), burst_(uint64_t(burst) * kToken), max_addresses_(max_addresses) {
  if (per_second == 0 || burst == 0 || max_addresses == 0)
    throw std::invalid_argument("connection rate limit: the rate must be positive, the burst at least 1 and "
                                "at least one address remembered");
}

uint64_t ConnectionRateLimit::refilled(const Bucket& bucket, uint64_t now_us) const {
  // A clock that went back refills nothing rather than draining the bucket; a long silence
  // refills the burst without overflowing.
  const uint64_t elapsed_us = now_us > bucket.last_us ? now_us - bucket.last_us : 0;
  if (elapsed_us >= burst_ / per_second_) return burst_;
  return std::min(burst_, bucket.tokens + elapsed_us * per_second_);
}

void ConnectionRateLimit::make_room(uint64_t now_us) {
  // Addresses whose bucket is full again are the same as forgotten ones: drop those first, and
  // only when every address is still over its rate the one seen longest ago.
  std::erase_if(buckets_, [&](const auto& entry) { return refilled(entry.second, now_us) >= burst_; });
  if (buckets_.size() < max_addresses_) return;
  buckets_.erase(std::min_element(buckets_.begin(), buckets_.end(), [](const auto& a, const auto& b) {
    return a.second.last_us < b.second.last_us;
  }));
}

bool ConnectionRateLimit::admit(const std::string& address, uint64_t now_us) {
  auto found = buckets_.find(address);
  if (found == buckets_.end()) {
    if (buckets_.size() >= max_addresses_) make_room(now_us);
    found = buckets_.emplace(address, Bucket{burst_, now_us}).first;
  }
  Bucket& bucket = found->second;
  bucket.tokens = refilled(bucket, now_us);
  bucket.last_us = std::max(bucket.last_us, now_us);
  if (bucket.tokens < kToken) return false;
  bucket.tokens -= kToken;
  return true;
}

}  // namespace rt::net
