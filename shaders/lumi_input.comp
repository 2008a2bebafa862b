#version 460
#extension GL_GOOGLE_include_directive : require
// Lumi-Net's input: each view's warped color and blending features box-filtered from the target's
// resolution to the network's (one scale x scale block per value), averaged over the block's
// pixels the view sees, so that a view seeing a quarter of a block still brings its true color
// rather than a darkened one; the fraction it sees is a channel of its own (coverage). A pixel
// counts as seen by the same test as the lumigraph blending's (ibr_blend), NaN features never.
#include "shared/config.h"
#include "shared/lumi_net.h"
#include "common/numeric.glsl"

layout(local_size_x = RT_TILE_X, local_size_y = RT_TILE_Y) in;

layout(binding = 0, rgba32f) uniform readonly image2D warped;    // rgb, visible; views in bands
layout(binding = 1, rgba32f) uniform readonly image2D features;  // angle, resolution, feather, visible
layout(std430, binding = 2) writeonly buffer Inputs { float inputs[]; };      // (views, 7, h, w)
layout(std430, binding = 3) writeonly buffer Coverage { float coverage[]; };  // (views, 1, h, w)
layout(push_constant) uniform Push { LumiScaleParams params; };

void main() {
  const ivec2 cell = ivec2(gl_GlobalInvocationID.xy);
  const int view = int(gl_GlobalInvocationID.z);
  const ivec2 small = ivec2(params.small_width, params.small_height);
  if (any(greaterThanEqual(cell, small)) || view >= int(params.views)) return;
  const ivec2 full = ivec2(params.width, params.height);
  const int scale = int(params.scale);
  float values[RT_LUMI_INPUT_CHANNELS];
  for (int c = 0; c < RT_LUMI_INPUT_CHANNELS; ++c) values[c] = 0.0;
  int seen = 0, pixels = 0;
  for (int dy = 0; dy < scale; ++dy)
    for (int dx = 0; dx < scale; ++dx) {
      const ivec2 p = cell * scale + ivec2(dx, dy);
      if (p.x >= full.x || p.y >= full.y) continue;
      ++pixels;
      const ivec2 texel = ivec2(p.x, p.y + view * full.y);
      const vec4 f = imageLoad(features, texel);
      if (!(f.w > 0.0) || !(f.z > 0.0) || !is_finite(f.x) || !is_finite(f.y) || !is_finite(f.z)) continue;
      const vec3 color = unit_or_zero(imageLoad(warped, texel).rgb);
      ++seen;
      values[0] += color.r;
      values[1] += color.g;
      values[2] += color.b;
      values[4] += max(f.x, 0.0);
      values[5] += max(f.y, 0.0);
      values[6] += f.z;
    }
  if (seen > 0)
    for (int c = 0; c < RT_LUMI_INPUT_CHANNELS; ++c) values[c] /= float(seen);
  values[3] = float(seen) / float(max(pixels, 1));
  const int plane = small.x * small.y, at = cell.y * small.x + cell.x;
  for (int c = 0; c < RT_LUMI_INPUT_CHANNELS; ++c) inputs[(view * RT_LUMI_INPUT_CHANNELS + c) * plane + at] = values[c];
  coverage[view * plane + at] = values[3];
}
