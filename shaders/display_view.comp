#version 460
#extension GL_GOOGLE_include_directive : require
// One of the window's views: a band of any image of the pipeline, fitted into the window with its
// aspect kept (black bars outside), each window pixel showing the source texel under its centre.
// Integer arithmetic throughout, so that the C++ reference picks the very same texel. A value that
// is not finite shows magenta: a debug view is where such values must stand out.
#include "shared/config.h"
#include "common/numeric.glsl"

layout(local_size_x = RT_TILE_X, local_size_y = RT_TILE_Y) in;

layout(binding = 0) uniform sampler2D source;  // any format; read with texelFetch
layout(binding = 1, rgba8) uniform writeonly image2D view;

layout(push_constant) uniform Params { DisplayViewParams params; };

const vec4 kNotFinite = vec4(1.0, 0.0, 1.0, 1.0);
const vec4 kNoDepth = vec4(0.0, 0.0, 0.25, 1.0);

float ramp(float value) {
  float span = params.high - params.low;
  return span > 0.0 ? clamp((value - params.low) / span, 0.0, 1.0) : 0.0;
}

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  ivec2 size = imageSize(view);
  if (any(greaterThanEqual(pixel, size))) return;
  int source_w = textureSize(source, 0).x;
  int band_h = int(params.band_height);
  if (source_w <= 0 || band_h <= 0) {
    imageStore(view, pixel, vec4(0.0, 0.0, 0.0, 1.0));
    return;
  }
  // The drawn rectangle: as wide as the window, or as high, whichever keeps the band inside.
  ivec2 drawn = size.x * band_h <= size.y * source_w ? ivec2(size.x, (band_h * size.x) / source_w)
                                                     : ivec2((source_w * size.y) / band_h, size.y);
  ivec2 offset = (size - drawn) / 2;
  ivec2 inside = pixel - offset;
  if (any(lessThan(inside, ivec2(0))) || any(greaterThanEqual(inside, drawn))) {
    imageStore(view, pixel, vec4(0.0, 0.0, 0.0, 1.0));
    return;
  }
  ivec2 texel = ivec2((inside.x * source_w) / drawn.x, int(params.band_y0) + (inside.y * band_h) / drawn.y);
  vec4 value = texelFetch(source, texel, 0);
  vec4 shown;
  if (params.mode == RT_VIEW_COLOR) {
    bool finite = is_finite(value.r) && is_finite(value.g) && is_finite(value.b);
    shown = finite ? vec4(clamp(value.rgb, 0.0, 1.0), 1.0) : kNotFinite;
  } else {
    float v = value[min(params.channel, 3u)];
    if (!is_finite(v)) shown = kNotFinite;
    else if (params.mode == RT_VIEW_DEPTH) shown = v > 0.0 ? vec4(vec3(1.0 - ramp(v)), 1.0) : kNoDepth;
    else shown = vec4(vec3(ramp(v)), 1.0);
  }
  imageStore(view, pixel, shown);
}
