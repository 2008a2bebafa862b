#version 460
#extension GL_GOOGLE_include_directive : require
// Lumi-Net's cross-view pooling: the mean and the maximum of each feature over the views that see
// the pixel (coverage > 0), concatenated after each view's own features, so that the next layer
// weighs a view knowing what the others offer. A view that does not see the pixel still gets the
// pooled features (the network may learn from them) but adds nothing to them; where no view sees
// the pixel both are 0.
#include "shared/config.h"
#include "shared/lumi_net.h"

layout(local_size_x = RT_TILE_X, local_size_y = RT_TILE_Y) in;
layout(constant_id = 0) const int channels = 1;  // set by LumiPoolPass; placeholder never used

layout(std430, binding = 0) readonly buffer Source { float source[]; };      // (views, C, h, w)
layout(std430, binding = 1) readonly buffer Coverage { float coverage[]; };  // (views, 1, h, w)
layout(std430, binding = 2) writeonly buffer Result { float result[]; };     // (views, 3C, h, w)
layout(push_constant) uniform Push { LumiTensorParams params; };

void main() {
  const ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (pixel.x >= int(params.width) || pixel.y >= int(params.height)) return;
  const int plane = int(params.width * params.height), at = pixel.y * int(params.width) + pixel.x;
  const int views = int(params.views);
  int seeing = 0;
  for (int v = 0; v < views; ++v)
    if (coverage[v * plane + at] > 0.0) ++seeing;
  for (int c = 0; c < channels; ++c) {
    float sum = 0.0, largest = 0.0;
    bool first = true;
    for (int v = 0; v < views; ++v) {
      const float value = source[(v * channels + c) * plane + at];
      result[(v * 3 * channels + c) * plane + at] = value;
      if (!(coverage[v * plane + at] > 0.0)) continue;
      sum += value;
      largest = first ? value : max(largest, value);
      first = false;
    }
    const float mean = seeing > 0 ? sum / float(seeing) : 0.0;
    for (int v = 0; v < views; ++v) {
      result[(v * 3 * channels + channels + c) * plane + at] = mean;
      result[(v * 3 * channels + 2 * channels + c) * plane + at] = largest;
    }
  }
}
