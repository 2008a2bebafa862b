#include "image/pixel_mask.h"

#include <algorithm>
#include <numeric>

namespace rt {

PixelMask dilate_mask(const PixelMask& mask, uint32_t width, uint32_t height, int radius) {
  // Separable: a square structuring element is a row pass then a column pass.
  PixelMask rows(mask.size(), 0), out(mask.size(), 0);
  const int w = int(width), h = int(height), r = std::max(radius, 0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (!mask[size_t(y) * width + size_t(x)]) continue;
      for (int nx = std::max(0, x - r); nx <= std::min(w - 1, x + r); ++nx) rows[size_t(y) * width + size_t(nx)] = 1;
    }
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (!rows[size_t(y) * width + size_t(x)]) continue;
      for (int ny = std::max(0, y - r); ny <= std::min(h - 1, y + r); ++ny) out[size_t(ny) * width + size_t(x)] = 1;
    }
  return out;
}

size_t count_set(const PixelMask& mask) {
  return size_t(std::count_if(mask.begin(), mask.end(), [](uint8_t v) { return v != 0; }));
}

}  // namespace rt
