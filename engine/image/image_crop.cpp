#include "image/image_crop.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace rt {

PixelBox nonzero_box(const HostImage& image) {
  uint32_t x0 = image.width, y0 = image.height, x1 = 0, y1 = 0;
  for (uint32_t y = 0; y < image.height; ++y)
    for (uint32_t x = 0; x < image.width; ++x)
      if (image.at(x, y, 0) > 0.0f) {
        x0 = std::min(x0, x), y0 = std::min(y0, y);
        x1 = std::max(x1, x + 1), y1 = std::max(y1, y + 1);
      }
  if (x1 <= x0 || y1 <= y0) return {};
  return {x0, y0, x1 - x0, y1 - y0};
}

HostImage crop(const HostImage& image, const PixelBox& box) {
  if (uint64_t(box.x) + box.width > image.width || uint64_t(box.y) + box.height > image.height)
    throw std::invalid_argument("crop: box " + std::to_string(box.width) + "x" + std::to_string(box.height) + " at (" +
                                std::to_string(box.x) + ", " + std::to_string(box.y) + ") reaches outside the " +
                                std::to_string(image.width) + "x" + std::to_string(image.height) + " image");
  HostImage part(box.width, box.height, image.format);
  const size_t row = size_t(box.width) * image.channels();
  for (uint32_t y = 0; y < box.height; ++y)
    std::copy_n(image.texels.begin() + ptrdiff_t(image.index(box.x, box.y + y)), row,
                part.texels.begin() + ptrdiff_t(part.index(0, y)));
  return part;
}

HostImage paste_on_zero(const HostImage& part, uint32_t x, uint32_t y, uint32_t width, uint32_t height) {
  if (uint64_t(x) + part.width > width || uint64_t(y) + part.height > height)
    throw std::invalid_argument("paste: a " + std::to_string(part.width) + "x" + std::to_string(part.height) +
                                " part at (" + std::to_string(x) + ", " + std::to_string(y) + ") does not fit in " +
                                std::to_string(width) + "x" + std::to_string(height));
  HostImage image(width, height, part.format);
  const size_t row = size_t(part.width) * part.channels();
  for (uint32_t row_index = 0; row_index < part.height; ++row_index)
    std::copy_n(part.texels.begin() + ptrdiff_t(part.index(0, row_index)), row,
                image.texels.begin() + ptrdiff_t(image.index(x, y + row_index)));
  return image;
}

}  // namespace rt
