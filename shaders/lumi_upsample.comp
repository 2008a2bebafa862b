#version 460
#extension GL_GOOGLE_include_directive : require
// Lumi-Net's weights and alpha from the network's resolution to the target's: bilinear, with the
// half-pixel centres of PyTorch's interpolate(align_corners=False) and ONNX's Resize, so that the
// training's upsampling and this one agree; the edge clamps as theirs does.
#include "shared/config.h"
#include "shared/lumi_net.h"

layout(local_size_x = RT_TILE_X, local_size_y = RT_TILE_Y) in;

layout(std430, binding = 0) readonly buffer Small { float small[]; };  // (1, planes, small_h, small_w)
layout(std430, binding = 1) writeonly buffer Full { float full[]; };   // (1, planes, h, w)
layout(push_constant) uniform Push { LumiScaleParams params; };        // views: the plane count

// Where a target pixel's centre falls on the small grid: the two neighbours and the blend.
void source_of(int x, int small_size, out int low, out int high, out float t) {
  const float s = max((float(x) + 0.5) / float(params.scale) - 0.5, 0.0);
  low = min(int(s), small_size - 1);
  high = min(low + 1, small_size - 1);
  t = s - float(low);
}

void main() {
  const ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (pixel.x >= int(params.width) || pixel.y >= int(params.height)) return;
  const int sw = int(params.small_width), sh = int(params.small_height);
  int x0, x1, y0, y1;
  float tx, ty;
  source_of(pixel.x, sw, x0, x1, tx);
  source_of(pixel.y, sh, y0, y1, ty);
  const int small_plane = sw * sh, full_plane = int(params.width * params.height);
  for (int p = 0; p < int(params.views); ++p) {
    const int base = p * small_plane;
    const float top = mix(small[base + y0 * sw + x0], small[base + y0 * sw + x1], tx);
    const float bottom = mix(small[base + y1 * sw + x0], small[base + y1 * sw + x1], tx);
    full[p * full_plane + pixel.y * int(params.width) + pixel.x] = mix(top, bottom, ty);
  }
}
