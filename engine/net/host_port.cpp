#include <algorithm>
#include <stdexcept>

#include "net/session.h"

namespace rt::net {

std::pair<std::string, uint16_t> parse_host_port(const std::string& text) {
  const size_t colon = text.rfind(':');
  if (colon == std::string::npos || colon == 0 || colon + 1 == text.size())
    throw std::invalid_argument("'" + text + "' is not HOST:PORT");
  std::string host = text.substr(0, colon);
  if (host.front() == '[' && host.back() == ']') host = host.substr(1, host.size() - 2);
  const std::string port_text = text.substr(colon + 1);
  if (port_text.size() > 5 || !std::all_of(port_text.begin(), port_text.end(), [](char c) { return c >= '0' && c <= '9'; }))
    throw std::invalid_argument("'" + text + "': port '" + port_text + "' is not a number");
  const unsigned long port = std::stoul(port_text);
  if (port == 0 || port > 65535) throw std::invalid_argument("'" + text + "': port must be 1..65535");
  return {host, uint16_t(port)};
}

}  // namespace rt::net
