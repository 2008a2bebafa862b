#include "passes/display_view.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "display_view.comp.h"

namespace rt::passes {
namespace {

// The band inside the source: a view picked for another image (an atlas with fewer views) still
// shows something valid rather than reading outside.
DisplayViewMapping within(DisplayViewMapping mapping, uint32_t source_height) {
  mapping.band_y0 = std::min(mapping.band_y0, source_height ? source_height - 1 : 0);
  const uint32_t rest = source_height - mapping.band_y0;
  mapping.band_height = mapping.band_height == 0 ? rest : std::min(mapping.band_height, rest);
  mapping.channel = std::min(mapping.channel, 3u);
  return mapping;
}

}  // namespace

DisplayViewPass::DisplayViewPass(vk::Context& context)
    : kernel_(context, "display_view", display_view_comp_spirv), sampler_(context, "display view texels", VK_FILTER_NEAREST) {}

void DisplayViewPass::add_to(vk::FrameGraph& graph, vk::Image& source, vk::Image& view,
                             std::function<DisplayViewMapping()> mapping, const std::string& pass_name) const {
  if (view.pixel_format() != PixelFormat::RGBA8) throw std::invalid_argument(pass_name + ": the view must be rgba8");
  graph.add_compute_pass({
      .name = pass_name,
      .kernel = &kernel_,
      .bindings = {{"source", &source, &sampler_}, {"view", &view}},
      .threads = {view.width(), view.height(), 1},
      .push_constants = vk::push_constants_from<shader_abi::DisplayViewParams>(
          [mapping = std::move(mapping), height = source.height()] {
            const DisplayViewMapping m = within(mapping(), height);
            return shader_abi::DisplayViewParams{m.mode, m.channel, m.band_y0, m.band_height, m.low, m.high};
          }),
  });
}

HostImage display_view_reference(const HostImage& source, const DisplayViewMapping& requested, uint32_t width,
                                 uint32_t height) {
  const DisplayViewMapping m = within(requested, source.height);
  HostImage view(width, height, PixelFormat::RGBA8);
  const int64_t w = width, h = height, source_w = source.width, band_h = m.band_height;
  auto ramp = [&](float value) {
    const float span = m.high - m.low;
    return span > 0.0f ? std::clamp((value - m.low) / span, 0.0f, 1.0f) : 0.0f;
  };
  auto put = [&](uint32_t x, uint32_t y, float r, float g, float b) {
    for (uint32_t c = 0; c < 3; ++c) view.at(x, y, c) = std::round((c == 0 ? r : c == 1 ? g : b) * 255.0f) / 255.0f;
    view.at(x, y, 3) = 1.0f;
  };
  const bool wide = w * band_h <= h * source_w;
  const int64_t drawn_w = source_w <= 0 || band_h <= 0 ? 0 : wide ? w : (source_w * h) / band_h;
  const int64_t drawn_h = source_w <= 0 || band_h <= 0 ? 0 : wide ? (band_h * w) / source_w : h;
  const int64_t offset_x = (w - drawn_w) / 2, offset_y = (h - drawn_h) / 2;
  for (uint32_t y = 0; y < height; ++y)
    for (uint32_t x = 0; x < width; ++x) {
      const int64_t ix = int64_t(x) - offset_x, iy = int64_t(y) - offset_y;
      if (ix < 0 || iy < 0 || ix >= drawn_w || iy >= drawn_h) {
        put(x, y, 0, 0, 0);
        continue;
      }
      const uint32_t sx = uint32_t((ix * source_w) / drawn_w), sy = m.band_y0 + uint32_t((iy * band_h) / drawn_h);
      // A one-channel source reads as (r, 0, 0, 1), as a sampled image does.
      auto channel = [&](uint32_t c) {
        return c < source.channels() ? source.at(sx, sy, c) : c == 3 ? 1.0f : 0.0f;
      };
      if (m.mode == RT_VIEW_COLOR) {
        const float r = channel(0), g = channel(1), b = channel(2);
        if (!std::isfinite(r) || !std::isfinite(g) || !std::isfinite(b)) put(x, y, 1, 0, 1);
        else put(x, y, std::clamp(r, 0.0f, 1.0f), std::clamp(g, 0.0f, 1.0f), std::clamp(b, 0.0f, 1.0f));
        continue;
      }
      const float v = channel(m.channel);
      if (!std::isfinite(v)) put(x, y, 1, 0, 1);
      else if (m.mode == RT_VIEW_DEPTH) {
        if (v > 0.0f) {
          const float g = 1.0f - ramp(v);
          put(x, y, g, g, g);
        } else put(x, y, 0, 0, 0.25f);
      } else {
        const float g = ramp(v);
        put(x, y, g, g, g);
      }
    }
  return view;
}

}  // namespace rt::passes
