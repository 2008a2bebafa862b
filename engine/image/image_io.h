#pragma once
// Images to and from files through OpenCV: PNG (8 or 16 bits per channel) for looking at,
// EXR (32-bit float, values kept exactly) for debugging and for tests. R32F images are written
// as one grey channel, RGBA images with their alpha.
#include <filesystem>

#include "image/host_image.h"

namespace rt {

enum class PngDepth { Eight, Sixteen };

// The format follows the extension (.png or .exr). Values are clamped to [0, 1] for PNG
// (NaN written as 0); EXR keeps them as they are. Throws with the path and the reason.
void write_image(const std::filesystem::path& path, const HostImage& image, PngDepth depth = PngDepth::Eight);

// Reads a PNG (8 or 16 bits, scaled to [0, 1]) or an EXR, as R32F (one channel) or RGBA32F.
HostImage read_image(const std::filesystem::path& path);

// R16U images (depth in millimetres) are written by write_image as 16-bit PNG of the values
// themselves, unscaled; this reads one back exactly. Errors name the file and what is wrong.
HostImage read_depth_png(const std::filesystem::path& path);

}  // namespace rt
