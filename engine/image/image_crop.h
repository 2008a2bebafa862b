#pragma once
// Cutting the part of an image that holds something, and putting it back: the receiver keeps a
// short history of hand renders, and the hand covers a small part of the view.
#include <cstdint>

#include "image/host_image.h"

namespace rt {

struct PixelBox {
  uint32_t x = 0, y = 0, width = 0, height = 0;  // empty when width or height is 0
  bool empty() const { return width == 0 || height == 0; }
};

// The smallest box holding every pixel whose first channel is above zero (NaN counts as nothing).
PixelBox nonzero_box(const HostImage& image);

// The box's pixels, all channels; throws std::invalid_argument when it reaches outside the image.
HostImage crop(const HostImage& image, const PixelBox& box);

// A width x height image of `part`'s format, zero except `part` placed at (x, y); throws
// std::invalid_argument when the part does not fit there.
HostImage paste_on_zero(const HostImage& part, uint32_t x, uint32_t y, uint32_t width, uint32_t height);

}  // namespace rt
