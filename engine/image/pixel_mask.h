#pragma once
// Binary masks over an image's pixels (row-major, one byte per pixel, 1 = set), for the
// evaluations' regions.
#include <cstddef>
#include <cstdint>
#include <vector>

namespace rt {

using PixelMask = std::vector<uint8_t>;

// Every pixel within `radius` (Chebyshev distance) of a set one; radius 0 copies.
PixelMask dilate_mask(const PixelMask& mask, uint32_t width, uint32_t height, int radius);
size_t count_set(const PixelMask& mask);

}  // namespace rt
