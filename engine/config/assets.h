#pragma once
// Where the assets are (assets/ of the source tree, or $REMOTETOUCH_ASSETS for an installed copy),
// and the scripts a command runs (scripts/ of the source tree, or $REMOTETOUCH_SCRIPTS).
#include <filesystem>

namespace rt::config {

std::filesystem::path assets_dir();
std::filesystem::path scripts_dir();

}  // namespace rt::config
