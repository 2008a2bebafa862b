#include "media/ice_servers.h"

#include <gst/gst.h>
#include <gst/webrtc/webrtc.h>
#include <nice/agent.h>

#include <algorithm>
#include <memory>
#include <stdexcept>

namespace rt::media {
namespace {

constexpr size_t kMaxUrlBytes = 1024;

struct ParsedServer {
  std::string scheme, user, password, host;
  unsigned port = 0;
};

// The URL as an error message may show it: without its password, which would end up in logs.
std::string url_without_password(const std::string& url) {
  std::string out = url.size() > 80 ? url.substr(0, 80) + "..." : url;
  const size_t start = out.find("://"), at = out.rfind('@');
  if (start != std::string::npos && at != std::string::npos && at > start)
    if (const size_t colon = out.find(':', start + 3); colon < at) out.replace(colon + 1, at - colon - 1, "***");
  return out;
}

ParsedServer parse_server(const std::string& url, const char* option, const char* form) {
  const auto refuse = [&](const std::string& why) {
    return std::invalid_argument(std::string(option) + " '" + url_without_password(url) + "': " + why + " (expected " + form + ")");
  };
  if (url.empty()) throw refuse("empty");
  if (url.size() > kMaxUrlBytes) throw refuse("longer than " + std::to_string(kMaxUrlBytes) + " bytes");
  if (std::any_of(url.begin(), url.end(), [](char c) { return c <= ' ' || c == 0x7f; }))
    throw refuse("a space or control character in it");
  if (!gst_is_initialized()) gst_init(nullptr, nullptr);
  std::unique_ptr<GstUri, decltype(&gst_uri_unref)> uri(gst_uri_from_string(url.c_str()), &gst_uri_unref);
  if (!uri || !gst_uri_get_scheme(uri.get())) throw refuse("not a URL");
  ParsedServer out;
  out.scheme = gst_uri_get_scheme(uri.get());
  std::transform(out.scheme.begin(), out.scheme.end(), out.scheme.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  if (const char* host = gst_uri_get_host(uri.get())) out.host = host;
  if (out.host.empty()) throw refuse("no host");
  if (const char* userinfo = gst_uri_get_userinfo(uri.get())) {
    const std::string info = userinfo;
    const size_t colon = info.find(':');
    out.user = info.substr(0, colon);
    if (colon != std::string::npos) out.password = info.substr(colon + 1);
  }
  out.port = gst_uri_get_port(uri.get());
  // GstUri keeps a port it could not read as none: a port in the text that it did not take is bad.
  const size_t host_end = url.find(out.host) + out.host.size();
  if (out.port == GST_URI_NO_PORT && host_end < url.size() && url[host_end] == ':') throw refuse("a port that is not a number from 1 to 65535");
  if (out.port != GST_URI_NO_PORT && (out.port == 0 || out.port > 65535)) throw refuse("port " + std::to_string(out.port) + " is not from 1 to 65535");
  const gchar* path = gst_uri_get_path(uri.get());
  if ((path && *path && std::string(path) != "/") || gst_uri_get_query_table(uri.get()) || gst_uri_get_fragment(uri.get()))
    throw refuse("a path, query or fragment, which an ICE server has not");
  return out;
}

}  // namespace

std::string parse_stun_url(const std::string& url) {
  constexpr const char* form = "stun://HOST:PORT";
  ParsedServer s = parse_server(url, "--stun", form);
  if (s.scheme != "stun") throw std::invalid_argument("--stun '" + url + "': the scheme must be stun, not '" + s.scheme + "' (expected " + form + ")");
  if (!s.user.empty() || !s.password.empty())
    throw std::invalid_argument("--stun '" + url + "': a STUN server takes no user or password (expected " + form + ")");
  if (s.port == GST_URI_NO_PORT) s.port = 3478;
  return "stun://" + s.host + ":" + std::to_string(s.port);
}

std::string parse_turn_url(const std::string& url) {
  constexpr const char* form = "turn://USER:PASS@HOST:PORT";
  ParsedServer s = parse_server(url, "--turn", form);
  if (s.scheme != "turn" && s.scheme != "turns")
    throw std::invalid_argument("--turn '" + url_without_password(url) + "': the scheme must be turn or turns, not '" + s.scheme +
                                "' (expected " + form + ")");
  if (s.user.empty() || s.password.empty())
    throw std::invalid_argument("--turn '" + url_without_password(url) + "': a TURN relay needs a user and a password (expected " +
                                std::string(form) + ")");
  if (s.port == GST_URI_NO_PORT) s.port = s.scheme == "turns" ? 5349 : 3478;
  return s.scheme + "://" + s.user + ":" + s.password + "@" + s.host + ":" + std::to_string(s.port);
}

void configure_ice(GstElement* webrtc, const std::string& stun_server, const std::string& turn_server, bool relay_only,
                   const std::vector<std::string>& local_addresses) {
  if (relay_only && turn_server.empty()) throw std::runtime_error("a relay-only call needs a TURN server (--turn)");
  if (!stun_server.empty()) g_object_set(webrtc, "stun-server", stun_server.c_str(), nullptr);
  if (!turn_server.empty()) g_object_set(webrtc, "turn-server", turn_server.c_str(), nullptr);
  if (relay_only) g_object_set(webrtc, "ice-transport-policy", GST_WEBRTC_ICE_TRANSPORT_POLICY_RELAY, nullptr);
  // libnice gathers on every interface but loopback unless told its addresses: name them.
  GObject* ice = nullptr;
  g_object_get(webrtc, "ice-agent", &ice, nullptr);
  NiceAgent* agent = nullptr;
  if (ice) g_object_get(ice, "agent", &agent, nullptr);
  if (!agent) throw std::runtime_error("webrtcbin has no libnice agent (gstreamer1.0-nice)");
  g_object_set(ice, "ice-tcp", FALSE, nullptr);  // UDP only: nothing here needs TCP candidates
  for (const std::string& address : local_addresses) {
    NiceAddress nice;
    nice_address_init(&nice);
    if (!nice_address_set_from_string(&nice, address.c_str()))
      throw std::runtime_error("not an IP address for ICE: '" + address + "'");
    nice_agent_add_local_address(agent, &nice);
  }
  g_object_unref(agent);
  g_object_unref(ice);
}

}  // namespace rt::media
