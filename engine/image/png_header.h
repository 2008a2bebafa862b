#pragma once
// A PNG file's header (signature and IHDR chunk), read before anything is decoded: an image from a
// recording must be a PNG of the size and kind the calibration expects, so that a small file that
// declares a huge image, or a file of another format under a .png name, is refused before OpenCV
// allocates or runs another decoder for it.
#include <cstdint>
#include <filesystem>
#include <string>

namespace rt {

struct PngHeader {
  uint32_t width = 0, height = 0;
  uint8_t bit_depth = 0;
  uint8_t color_type = 0;  // 0 gray, 2 RGB, 3 palette, 4 gray+alpha, 6 RGBA
};

// Throws std::runtime_error naming the file: missing, too short, not a PNG, or a broken IHDR.
PngHeader read_png_header(const std::filesystem::path& path);

enum class PngKind { Color8, Depth16 };  // 8-bit RGB or RGBA; 16-bit one-channel
// Throws std::runtime_error naming the file and what differs, unless the header is `kind` at
// width x height.
void check_png_header(const std::filesystem::path& path, uint32_t width, uint32_t height, PngKind kind);

}  // namespace rt
