#pragma once
// The ICE servers a WebRTC call may use, as the site's options name them, checked before webrtcbin
// sees them (it takes a bad URL silently and gathers nothing from it):
//   --stun stun://HOST:PORT                 the address a NAT shows the outside (port 3478 if left out)
//   --turn turn://USER:PASS@HOST:PORT        a relay (coturn) for networks that let nothing else
//          turns://USER:PASS@HOST:PORT       through; turns over TLS (ports 3478 and 5349 if left out)
// Parsed by GStreamer's GstUri. Each returns the URL as webrtcbin's stun-server / turn-server
// properties take it, or throws std::invalid_argument naming what is wrong.
#include <string>

namespace rt::media {

std::string parse_stun_url(const std::string& url);
std::string parse_turn_url(const std::string& url);

}  // namespace rt::media
