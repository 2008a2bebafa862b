#pragma once
// Where the assets are (assets/ of the source tree, or $REMOTETOUCH_ASSETS for an installed copy).
#include <filesystem>

namespace rt::config {

std::filesystem::path assets_dir();

}  // namespace rt::config
