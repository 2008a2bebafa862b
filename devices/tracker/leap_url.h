#pragma once
// The Leap service's address, apart from the client that uses it (leap_service.h), so that what
// only checks an address (the site file's reader, its fuzzer) does not compile the WebSocket client.
#include <string>

namespace rt::devices {

struct LeapUrl {
  std::string host, port, path;
  std::string text() const { return "ws://" + host + ":" + port + path; }
};
// "ws://HOST[:PORT][/PATH]", the port 6437 and the path /v6.json by default. Throws
// std::invalid_argument saying what is wrong.
LeapUrl parse_leap_url(const std::string& url);
inline constexpr const char* kDefaultLeapUrl = "ws://127.0.0.1:6437/v6.json";

}  // namespace rt::devices
