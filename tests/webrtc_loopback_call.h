#pragma once
// Two WebRTC peers in one process over loopback (127.0.0.1 only), for the tests of media::WebRtcPeer.
#include <catch2/catch.hpp>

#include <chrono>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "media/synthetic_portrait.h"
#include "media/webrtc_peer.h"

namespace rt::test {

using media::ChannelGuard;
using media::Signalling;
using media::WebRtcPeer;
using media::WebRtcPeerOptions;
using media::synthetic_portrait;

// The two peers and the signalling between them: callbacks (on GStreamer's threads) queue what
// one peer says; pump() hands it to the other on the test's thread.
class LoopbackWebRtcCall {
 public:
  // `adjust` changes both peers' options (the offerer's, then the answerer's) before they are made.
  LoopbackWebRtcCall(uint32_t width, uint32_t height, std::shared_ptr<ChannelGuard> offerer_guard = nullptr,
                     std::shared_ptr<ChannelGuard> answerer_guard = nullptr,
                     const std::function<void(WebRtcPeerOptions&)>& adjust = {}) {
    WebRtcPeerOptions a;
    a.name = "A";
    a.offerer = true;
    a.width = width;
    a.height = height;
    a.color_kbps = 1500;
    a.depth_kbps = 800;
    WebRtcPeerOptions b = a;
    b.name = "B";
    b.offerer = false;
    b.max_queued_portraits = 64;
    a.guard = std::move(offerer_guard);
    b.guard = std::move(answerer_guard);
    if (adjust) adjust(a), adjust(b);
    offerer = std::make_unique<WebRtcPeer>(a, signalling_to(true));
    answerer = std::make_unique<WebRtcPeer>(b, signalling_to(false));
  }

  void pump() {
    std::vector<Said> said;
    {
      std::lock_guard lock(mutex_);
      said.swap(queue_);
    }
    for (const Said& s : said) {
      WebRtcPeer& to = s.to_answerer ? *answerer : *offerer;
      if (s.description) {
        const std::string error = to.set_remote_description(s.type, s.text);
        INFO(error);
        REQUIRE(error.empty());
      } else {
        to.add_ice_candidate(s.mline, s.text);
        std::lock_guard lock(mutex_);
        candidates.push_back(s.text);
      }
    }
  }

  // The offer needs the tracks' caps, which come with the first portrait.
  bool connect(uint32_t width, uint32_t height, std::chrono::seconds timeout = std::chrono::seconds(15)) {
    offerer->send_portrait(synthetic_portrait(width, height, 1000));
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < deadline) {
      pump();
      if (offerer->connected() && answerer->connected()) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return false;
  }

  std::unique_ptr<WebRtcPeer> offerer, answerer;
  std::vector<std::string> candidates;

 private:
  struct Said {
    bool to_answerer = false, description = false;
    std::string type, text;
    unsigned mline = 0;
  };
  Signalling signalling_to(bool from_offerer) {
    Signalling s;
    s.on_description = [this, from_offerer](const std::string& type, const std::string& sdp) {
      std::lock_guard lock(mutex_);
      queue_.push_back({from_offerer, true, type, sdp, 0});
    };
    s.on_candidate = [this, from_offerer](unsigned mline, const std::string& candidate) {
      std::lock_guard lock(mutex_);
      queue_.push_back({from_offerer, false, "", candidate, mline});
    };
    return s;
  }
  std::mutex mutex_;
  std::vector<Said> queue_;
};

}  // namespace rt::test
