#version 460
#extension GL_GOOGLE_include_directive : require
// The tiles of the target view that hold a surface, listed for ibr_warp_blend to run over, and
// the portrait zeroed everywhere (the warp then writes the listed tiles). llvmpipe runs every
// instruction of a shader for every group of invocations, whatever the branches decide, so the
// warp over a tile without a surface would cost as much as over one with; a dispatch over the
// listed tiles alone skips them.
#include "shared/config.h"

layout(local_size_x = RT_TILE_X, local_size_y = RT_TILE_Y) in;

layout(binding = 0, r32f) uniform readonly image2D fused_depth;  // 0 = nothing
layout(binding = 1, rgba32f) uniform writeonly image2D portrait;
layout(binding = 2, r32f) uniform writeonly image2D portrait_depth;
// The warp's workgroup counts (x: listed tiles, reset to 0 before this pass; y, z: 1).
layout(std430, binding = 3) buffer TileDispatch { uint tile_dispatch[3]; };
layout(std430, binding = 4) writeonly buffer Tiles { uvec2 tiles[]; };  // tile x, y, in no order

shared uint tile_has_surface;

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  bool in_image = all(lessThan(pixel, imageSize(fused_depth)));
  if (gl_LocalInvocationIndex == 0u) tile_has_surface = 0u;
  barrier();
  // A surface as the warp sees one (z > 0): an infinite depth counts, and is seen by no view.
  if (in_image && imageLoad(fused_depth, pixel).r > 0.0) atomicOr(tile_has_surface, 1u);
  if (in_image) {
    imageStore(portrait, pixel, vec4(0.0));
    imageStore(portrait_depth, pixel, vec4(0.0));
  }
  barrier();
  if (gl_LocalInvocationIndex == 0u && tile_has_surface != 0u) tiles[atomicAdd(tile_dispatch[0], 1u)] = gl_WorkGroupID.xy;
}
