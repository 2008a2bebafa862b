#version 460
#extension GL_GOOGLE_include_directive : require
// A plain image copy: the bandwidth roofline the benchmarks compare every pass against.
#include "shared/config.h"

layout(local_size_x = RT_ROW_X, local_size_y = 1) in;

layout(binding = 0, rgba32f) uniform readonly image2D source;
layout(binding = 1, rgba32f) uniform writeonly image2D destination;

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(pixel, imageSize(destination)))) return;
  imageStore(destination, pixel, imageLoad(source, pixel));
}
