// The STUN and TURN URLs a site is given (media/ice_servers.h): good ones come out as webrtcbin
// takes them, with the default ports; bad ones are refused naming what is wrong, and never with
// the TURN password in the message.
#include <catch2/catch.hpp>

#include <stdexcept>
#include <string>

#include "media/ice_servers.h"

using rt::media::parse_stun_url;
using rt::media::parse_turn_url;

namespace {
std::string ice_url_refusal(std::string (*parse)(const std::string&), const std::string& url) {
  try {
    parse(url);
  } catch (const std::invalid_argument& error) {
    return error.what();
  }
  return "";
}
}  // namespace

TEST_CASE("STUN and TURN URLs are read as webrtcbin takes them", "[media][ice]") {
  CHECK(parse_stun_url("stun://stun.example.org:19302") == "stun://stun.example.org:19302");
  CHECK(parse_stun_url("stun://127.0.0.1") == "stun://127.0.0.1:3478");
  CHECK(parse_turn_url("turn://alice:s3cret@turn.example.org:3478") == "turn://alice:s3cret@turn.example.org:3478");
  CHECK(parse_turn_url("turn://alice:s3cret@10.0.0.1") == "turn://alice:s3cret@10.0.0.1:3478");
  CHECK(parse_turn_url("turns://alice:s3cret@turn.example.org") == "turns://alice:s3cret@turn.example.org:5349");
}

TEST_CASE("bad STUN and TURN URLs are refused naming what is wrong", "[media][ice]") {
  const auto stun = [](const std::string& url) { return ice_url_refusal(parse_stun_url, url); };
  const auto turn = [](const std::string& url) { return ice_url_refusal(parse_turn_url, url); };
  CHECK_THAT(stun(""), Catch::Contains("empty"));
  CHECK_THAT(stun("stun.example.org:3478"), Catch::Contains("stun://HOST:PORT"));
  CHECK_THAT(stun("http://example.org:3478"), Catch::Contains("scheme must be stun"));
  CHECK_THAT(stun("stun://:3478"), Catch::Contains("no host"));
  CHECK_THAT(stun("stun://example.org:99999"), Catch::Contains("port"));
  CHECK_THAT(stun("stun://example.org:http"), Catch::Contains("not a URL"));
  CHECK_THAT(stun("stun://example.org:0"), Catch::Contains("port"));
  CHECK_THAT(stun("stun://u:p@example.org:3478"), Catch::Contains("no user or password"));
  CHECK_THAT(stun("stun://example.org:3478/path"), Catch::Contains("path"));
  CHECK_THAT(stun("stun://exa mple.org:3478"), Catch::Contains("space"));
  CHECK_THAT(stun("stun://" + std::string(2000, 'a')), Catch::Contains("longer than"));
  CHECK_THAT(turn("turn://example.org:3478"), Catch::Contains("needs a user and a password"));
  CHECK_THAT(turn("turn://alice@example.org:3478"), Catch::Contains("needs a user and a password"));
  CHECK_THAT(turn("stun://alice:pw@example.org:3478"), Catch::Contains("scheme must be turn or turns"));
  CHECK_THAT(turn("turn://alice:pw@:3478"), Catch::Contains("no host"));
  const std::string refused = turn("turn://alice:hunter2@example.org:70000");
  CHECK_THAT(refused, Catch::Contains("port"));
  CHECK_THAT(refused, !Catch::Contains("hunter2"));  // the password stays out of logs
  CHECK_THAT(refused, Catch::Contains("alice:***@"));
}
