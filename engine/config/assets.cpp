#include "config/assets.h"

#include <cstdlib>

namespace rt::config {

std::filesystem::path assets_dir() {
  const char* assets = std::getenv("REMOTETOUCH_ASSETS");
  return assets && *assets ? std::filesystem::path(assets) : std::filesystem::path(REMOTETOUCH_ASSETS_DIR);
}

}  // namespace rt::config
