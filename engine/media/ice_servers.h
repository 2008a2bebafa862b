#pragma once
// The ICE servers a WebRTC call may use, as the site's options name them, checked before webrtcbin
// sees them (it takes a bad URL silently and gathers nothing from it):
//   --stun stun://HOST:PORT                 the address a NAT shows the outside (port 3478 if left out)
//   --turn turn://USER:PASS@HOST:PORT        a relay (coturn) for networks that let nothing else
//          turns://USER:PASS@HOST:PORT       through; turns over TLS (ports 3478 and 5349 if left out)
// Parsed by GStreamer's GstUri. Each returns the URL as webrtcbin's stun-server / turn-server
// properties take it, or throws std::invalid_argument naming what is wrong.
#include <string>
#include <vector>

typedef struct _GstElement GstElement;

namespace rt::media {

std::string parse_stun_url(const std::string& url);
std::string parse_turn_url(const std::string& url);

// webrtcbin's ICE: the servers (checked by the two above), relay only or not, and the local
// addresses libnice gathers on (it skips loopback unless named). Throws std::runtime_error for a
// relay-only call without a TURN server, an address that is not one, or no libnice agent.
void configure_ice(GstElement* webrtc, const std::string& stun_server, const std::string& turn_server, bool relay_only,
                   const std::vector<std::string>& local_addresses);

}  // namespace rt::media
