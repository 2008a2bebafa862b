#include "config/assets.h"

#include <cstdlib>

namespace rt::config {
namespace {

std::filesystem::path from_environment(const char* variable, const char* built_in) {
  const char* value = std::getenv(variable);
  return value && *value ? std::filesystem::path(value) : std::filesystem::path(built_in);
}

}  // namespace

std::filesystem::path assets_dir() { return from_environment("REMOTETOUCH_ASSETS", REMOTETOUCH_ASSETS_DIR); }
std::filesystem::path scripts_dir() { return from_environment("REMOTETOUCH_SCRIPTS", REMOTETOUCH_SCRIPTS_DIR); }

}  // namespace rt::config
