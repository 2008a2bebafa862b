#version 460
#extension GL_GOOGLE_include_directive : require
// A plain storage-buffer copy, 16 bytes per element: the device's bandwidth roofline for kernels
// (no image layout, no format conversion). A grid-stride loop, so that any size fits one dispatch.
#include "shared/config.h"

layout(local_size_x = 256) in;

layout(binding = 0, std430) readonly buffer Source { uvec4 source[]; };
layout(binding = 1, std430) writeonly buffer Destination { uvec4 destination[]; };

layout(push_constant) uniform Params { BufferCopyParams params; };

void main() {
  uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
  for (uint i = gl_GlobalInvocationID.x; i < params.count; i += stride) destination[i] = source[i];
}
