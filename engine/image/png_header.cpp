#include "image/png_header.h"

#include <array>
#include <fstream>
#include <stdexcept>

namespace rt {
namespace {

uint32_t big_endian(const unsigned char* bytes) {
  return uint32_t(bytes[0]) << 24 | uint32_t(bytes[1]) << 16 | uint32_t(bytes[2]) << 8 | uint32_t(bytes[3]);
}

std::string size_text(uint32_t width, uint32_t height) { return std::to_string(width) + "x" + std::to_string(height); }

}  // namespace

PngHeader read_png_header(const std::filesystem::path& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) throw std::runtime_error("cannot read image '" + path.string() + "' (missing or unreadable)");
  // Signature (8), then the first chunk: length (4), type (4), IHDR's 13 bytes.
  std::array<unsigned char, 8 + 8 + 13> bytes{};
  file.read(reinterpret_cast<char*>(bytes.data()), std::streamsize(bytes.size()));
  if (file.gcount() != std::streamsize(bytes.size()))
    throw std::runtime_error("image '" + path.string() + "' is too short to be a PNG");
  static constexpr std::array<unsigned char, 8> kSignature = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (!std::equal(kSignature.begin(), kSignature.end(), bytes.begin()))
    throw std::runtime_error("image '" + path.string() + "' is not a PNG (its first bytes are not PNG's signature)");
  if (big_endian(&bytes[8]) != 13 || std::string(bytes.begin() + 12, bytes.begin() + 16) != "IHDR")
    throw std::runtime_error("image '" + path.string() + "' is a broken PNG (it does not begin with its IHDR chunk)");
  PngHeader header;
  header.width = big_endian(&bytes[16]);
  header.height = big_endian(&bytes[20]);
  header.bit_depth = bytes[24];
  header.color_type = bytes[25];
  if (header.width == 0 || header.height == 0)
    throw std::runtime_error("image '" + path.string() + "' is a PNG of " + size_text(header.width, header.height));
  return header;
}

void check_png_header(const std::filesystem::path& path, uint32_t width, uint32_t height, PngKind kind) {
  const PngHeader header = read_png_header(path);
  if (header.width != width || header.height != height)
    throw std::runtime_error("image '" + path.string() + "' is " + size_text(header.width, header.height) + ", expected " +
                             size_text(width, height) + " (not decoded)");
  const bool color = header.bit_depth == 8 && (header.color_type == 2 || header.color_type == 6);
  const bool depth = header.bit_depth == 16 && header.color_type == 0;
  if (kind == PngKind::Color8 && !color)
    throw std::runtime_error("image '" + path.string() + "' is not an 8-bit RGB or RGBA PNG (bit depth " +
                             std::to_string(header.bit_depth) + ", color type " + std::to_string(header.color_type) + ")");
  if (kind == PngKind::Depth16 && !depth)
    throw std::runtime_error("image '" + path.string() + "' is not a 16-bit one-channel PNG (bit depth " +
                             std::to_string(header.bit_depth) + ", color type " + std::to_string(header.color_type) + ")");
}

}  // namespace rt
