#pragma once
// Finding and reading the calibration photographs.
#include <opencv2/core.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace rt::calibration {

// Each entry is a shell-style pattern ("data/left*.jpg", expanded here so that a quoted
// pattern works) or a plain path. Returns the matches sorted and without duplicates; a pattern
// that matches nothing or a path that does not exist is an error that names it.
std::vector<std::filesystem::path> expand_image_patterns(const std::vector<std::string>& patterns);

// The image as 8-bit grey. The error says whether the file is missing, gzip-compressed (as
// Debian may ship documentation data) or not an image OpenCV can decode.
cv::Mat read_gray_image(const std::filesystem::path& path);

}  // namespace rt::calibration
