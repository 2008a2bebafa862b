#include "tracker/leap_url.h"

#include <cctype>
#include <stdexcept>

namespace rt::devices {

LeapUrl parse_leap_url(const std::string& url) {
  const std::string scheme = "ws://";
  if (url.rfind(scheme, 0) != 0) throw std::invalid_argument("Leap service URL '" + url + "' must start with ws://");
  for (const unsigned char c : url)
    if (std::iscntrl(c) || std::isspace(c))
      throw std::invalid_argument("Leap service URL '" + url + "' holds a space or a control character");
  const std::string rest = url.substr(scheme.size());
  const size_t slash = rest.find('/');
  const std::string authority = rest.substr(0, slash);
  LeapUrl parsed{authority, "6437", slash == std::string::npos ? "/v6.json" : rest.substr(slash)};
  if (const size_t colon = authority.rfind(':'); colon != std::string::npos) {
    parsed.host = authority.substr(0, colon);
    parsed.port = authority.substr(colon + 1);
    const bool digits = !parsed.port.empty() && parsed.port.size() <= 5 &&
                        parsed.port.find_first_not_of("0123456789") == std::string::npos;
    if (!digits || std::stoi(parsed.port) < 1 || std::stoi(parsed.port) > 65535)
      throw std::invalid_argument("Leap service URL '" + url + "': the port must be a number from 1 to 65535");
  }
  if (parsed.host.empty()) throw std::invalid_argument("Leap service URL '" + url + "' has no host");
  return parsed;
}

}  // namespace rt::devices
