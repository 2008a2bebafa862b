#include "passes/ibr_fill.h"

#include <algorithm>
#include <array>
#include <stdexcept>
#include <string>

#include "passes/common/reference_math.h"
#include "shared/config.h"

#include "ibr_fill.comp.h"

namespace rt::passes {
namespace {

uint32_t checked(uint32_t radius_px) {
  if (radius_px < 1 || radius_px > 64) throw std::invalid_argument("portrait hole filling: the radius must be 1..64 pixels");
  return radius_px;
}

bool covered(float alpha) { return alpha >= 0.5f; }

float finite_alpha(float alpha) { return alpha > 0.0f ? std::min(alpha, 1.0f) : 0.0f; }

}  // namespace

IbrFillPass::IbrFillPass(vk::Context& context, uint32_t radius_px)
    : radius_px_(checked(radius_px)),
      kernel_(context, "ibr_fill", ibr_fill_comp_spirv, {{"radius_px", int32_t(radius_px)}}) {}

void IbrFillPass::add_to(vk::FrameGraph& graph, vk::Image& portrait, IbrTiles& tiles, vk::Image& filled) const {
  if (filled.width() != portrait.width() || filled.height() != portrait.height())
    throw std::invalid_argument("ibr_fill: '" + filled.name() + "' is not the size of '" + portrait.name() + "'");
  if (tiles.layers() != 1 || !tiles.lists_bands_of(portrait))
    throw std::invalid_argument("ibr_fill: the tile list is not of '" + portrait.name() + "'");
  graph.add_compute_pass({
      .name = "ibr_fill",
      .kernel = &kernel_,
      .bindings = {{"portrait", &portrait}, {"filled", &filled}, {"Tiles", &tiles.tiles()}},
      .indirect = &tiles.dispatch(),
  });
}

HostImage ibr_fill_reference(const HostImage& portrait, uint32_t radius_px, const std::vector<TileIndex>& tiles) {
  checked(radius_px);
  if (portrait.format != PixelFormat::RGBA32F) throw std::invalid_argument("ibr_fill_reference: the portrait is not rgba32f");
  const int w = int(portrait.width), h = int(portrait.height), radius = int(radius_px);
  HostImage out(portrait.width, portrait.height, PixelFormat::RGBA32F, 0.0f);
  const std::array<std::array<int, 2>, 4> directions{{{1, 0}, {-1, 0}, {0, 1}, {0, -1}}};
  const auto texel = [&](int px, int py, uint32_t c) { return portrait.at(uint32_t(px), uint32_t(py), c); };
  std::vector<bool> listed(size_t(w) * size_t(h), false);
  for (const TileIndex& tile : tiles) {
    if (tile[2] != 0) throw std::invalid_argument("ibr_fill_reference: a tile of another layer than 0");
    for (uint32_t y = tile[1] * RT_TILE_Y; y < std::min<uint32_t>((tile[1] + 1) * RT_TILE_Y, uint32_t(h)); ++y)
      for (uint32_t x = tile[0] * RT_TILE_X; x < std::min<uint32_t>((tile[0] + 1) * RT_TILE_X, uint32_t(w)); ++x)
        listed[size_t(y) * size_t(w) + x] = true;
  }
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (!listed[size_t(y) * size_t(w) + size_t(x)]) continue;
      const float alpha = texel(x, y, 3);
      for (uint32_t c = 0; c < 3; ++c) out.at(uint32_t(x), uint32_t(y), c) = unit_or_zero(texel(x, y, c));
      out.at(uint32_t(x), uint32_t(y), 3) = finite_alpha(alpha);
      if (covered(alpha)) continue;
      float weighted[3] = {0, 0, 0}, weight_sum = 0;
      int enclosed_sides = 0;
      for (const auto& [dx, dy] : directions) {
        int distance = 1;
        for (; distance <= radius; ++distance) {
          const int px = x + dx * distance, py = y + dy * distance;
          if (px < 0 || py < 0 || px >= w || py >= h) {
            distance = radius + 1;
            break;
          }
          if (covered(texel(px, py, 3))) break;
        }
        if (distance > radius) break;
        const float weight = 1.0f / float(distance);
        for (uint32_t c = 0; c < 3; ++c)
          weighted[c] += unit_or_zero(texel(x + dx * distance, y + dy * distance, c)) * weight;
        weight_sum += weight;
        ++enclosed_sides;
      }
      if (enclosed_sides < 4) continue;
      for (uint32_t c = 0; c < 3; ++c) out.at(uint32_t(x), uint32_t(y), c) = weighted[c] / weight_sum;
      out.at(uint32_t(x), uint32_t(y), 3) = 1.0f;
    }
  return out;
}

}  // namespace rt::passes
