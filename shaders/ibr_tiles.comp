#version 460
#extension GL_GOOGLE_include_directive : require
// The tiles of the target view that hold a surface, listed for ibr_warp_blend to run over (the
// pass before this one zeroed the portrait; the warp writes the listed tiles). llvmpipe runs every
// instruction of a shader for every group of invocations, whatever the branches decide, so the
// warp over a tile without a surface would cost as much as over one with; a dispatch over the
// listed tiles alone skips them.
#include "shared/config.h"

layout(local_size_x = RT_TILE_X, local_size_y = RT_TILE_Y) in;

layout(binding = 0, r32f) uniform readonly image2D fused_depth;  // 0 = nothing
// The warp's workgroup counts (x: listed tiles, reset to 0 before this pass; y, z: 1).
layout(std430, binding = 1) buffer TileDispatch { uint tile_dispatch[3]; };
layout(std430, binding = 2) writeonly buffer Tiles { uvec4 tiles[]; };  // column, row, 0, 0; in no order

shared uint tile_has_surface;

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  bool in_image = all(lessThan(pixel, imageSize(fused_depth)));
  if (gl_LocalInvocationIndex == 0u) tile_has_surface = 0u;
  barrier();
  // A surface as the warp sees one (z > 0): an infinite depth counts, and is seen by no view.
  if (in_image && imageLoad(fused_depth, pixel).r > 0.0) atomicOr(tile_has_surface, 1u);
  barrier();
  if (gl_LocalInvocationIndex == 0u && tile_has_surface != 0u)
    tiles[atomicAdd(tile_dispatch[0], 1u)] = uvec4(gl_WorkGroupID.xy, 0u, 0u);
}
