#include "calibration/image_files.h"

#include <glob.h>

#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <array>
#include <fstream>

#include "calibration/calibration_error.h"

namespace rt::calibration {
namespace {

bool has_wildcard(const std::string& pattern) { return pattern.find_first_of("*?[") != std::string::npos; }

std::vector<std::filesystem::path> glob_paths(const std::string& pattern) {
  glob_t matches{};
  const int status = ::glob(pattern.c_str(), GLOB_ERR, nullptr, &matches);
  std::vector<std::filesystem::path> paths;
  if (status == 0)
    for (size_t i = 0; i < matches.gl_pathc; ++i) paths.emplace_back(matches.gl_pathv[i]);
  globfree(&matches);
  if (status == GLOB_NOMATCH) throw CalibrationError("images '" + pattern + "': the pattern matches no file");
  if (status == GLOB_ABORTED)
    throw CalibrationError("images '" + pattern + "': a folder on the way cannot be read (does it exist?)");
  if (status != 0) throw CalibrationError("images '" + pattern + "': cannot expand the pattern");
  return paths;
}

bool starts_with_gzip_magic(const std::filesystem::path& path) {
  std::ifstream file(path, std::ios::binary);
  std::array<unsigned char, 2> magic{};
  file.read(reinterpret_cast<char*>(magic.data()), magic.size());
  return file && magic[0] == 0x1f && magic[1] == 0x8b;
}

}  // namespace

std::vector<std::filesystem::path> expand_image_patterns(const std::vector<std::string>& patterns) {
  if (patterns.empty()) throw CalibrationError("no images given");
  std::vector<std::filesystem::path> paths;
  for (const std::string& pattern : patterns) {
    if (has_wildcard(pattern)) {
      const auto matches = glob_paths(pattern);
      paths.insert(paths.end(), matches.begin(), matches.end());
    } else {
      if (!std::filesystem::is_regular_file(pattern)) throw CalibrationError("image '" + pattern + "' does not exist");
      paths.emplace_back(pattern);
    }
  }
  std::sort(paths.begin(), paths.end());
  paths.erase(std::unique(paths.begin(), paths.end()), paths.end());
  // A pattern such as "*" also matches folders; they are not images.
  std::erase_if(paths, [](const std::filesystem::path& path) { return !std::filesystem::is_regular_file(path); });
  if (paths.empty()) throw CalibrationError("the image patterns match no regular file");
  return paths;
}

cv::Mat read_gray_image(const std::filesystem::path& path) {
  if (!std::filesystem::is_regular_file(path)) throw CalibrationError("image '" + path.string() + "' does not exist");
  if (starts_with_gzip_magic(path))
    throw CalibrationError("image '" + path.string() + "' is gzip-compressed; decompress it first (gunzip -k)");
  cv::Mat image;
  try {
    image = cv::imread(path.string(), cv::IMREAD_GRAYSCALE);
  } catch (const cv::Exception& error) {
    throw CalibrationError("image '" + path.string() + "' cannot be decoded: " + error.what());
  }
  if (image.empty()) throw CalibrationError("image '" + path.string() + "' cannot be read as an image (corrupt or not a picture)");
  return image;
}

}  // namespace rt::calibration
