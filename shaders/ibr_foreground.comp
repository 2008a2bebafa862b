#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
// Background removal (paper 3.1.1): each depth pixel of every view is unprojected into the site
// frame; it is foreground when it lies in the user's volume in front of the screen and enough of
// its neighbours do too at a similar depth. That last test cleans the silhouette: flying pixels
// between the user and the background and one-pixel fringes have too few agreeing neighbours.
// Views are bands of the atlases, one band per camera (z of the dispatch).
#include "shared/config.h"
#include "common/numeric.glsl"
#include "common/ibr_camera.glsl"

layout(local_size_x = RT_TILE_X, local_size_y = RT_TILE_Y) in;
// Knobs, all set by IbrForegroundPass, from ForegroundSettings (passes/ibr_foreground.h), where
// their defaults live: a kernel refuses to build while one is unset, so the initial values below
// are placeholders that GLSL requires, never used.
layout(constant_id = 0) const int min_support = 0;             // of 8 neighbours
layout(constant_id = 1) const float edge_tolerance_m = 0.0;   // neighbours closer than this agree

layout(binding = 0, r16ui) uniform readonly uimage2D depth_mm;   // views stacked in bands, 0 = invalid
layout(binding = 1, rgba32f) uniform readonly image2D depth_rays;  // site-frame ray (z = 1 in the camera), valid
layout(binding = 2, rgba32f) uniform writeonly image2D points;    // site xyz, camera z; 0 = none
// The tiles of the points atlas that hold a point, for ibr_splat to run over them alone (see
// ibr_tiles.comp): the splat's workgroup counts (x reset to 0 before this pass) and the tiles.
layout(std430, binding = 3) buffer TileDispatch { uint tile_dispatch[3]; };
layout(std430, binding = 4) writeonly buffer Tiles { uvec4 tiles[]; };  // column, row, view, 0
layout(push_constant) uniform Push { IbrForegroundParams params; };

// A depth pixel's site point and camera z (metres) when it lies in the volume, else 0. The ray
// atlas holds each pixel's ray in the site frame, so the point is the camera's position plus the
// depth times the ray.
vec4 volume_point(ivec2 pixel, int band, ivec2 size, vec3 camera_position) {
  if (any(lessThan(pixel, ivec2(0))) || any(greaterThanEqual(pixel, size))) return vec4(0.0);
  ivec2 texel = ivec2(pixel.x, pixel.y + band);
  uint millimetres = imageLoad(depth_mm, texel).r;
  vec4 ray = imageLoad(depth_rays, texel);
  if (millimetres == 0u || ray.w == 0.0) return vec4(0.0);
  float z = float(millimetres) * 0.001;
  vec3 site = camera_position + z * ray.xyz;
  bool inside = all(greaterThanEqual(site, params.volume_min.xyz)) && all(lessThanEqual(site, params.volume_max.xyz));
  return inside ? vec4(site, z) : vec4(0.0);
}

// The camera z of the workgroup's pixels and of a one-pixel border, each unprojected once: every
// pixel's support test reads its neighbours' from here instead of loading and transforming them
// again. Each invocation keeps its own pixel's point; the support test needs only the others' z.
const int kTileWidth = RT_TILE_X + 2, kTileHeight = RT_TILE_Y + 2;
const int kBorder = 2 * kTileWidth + 2 * RT_TILE_Y;
shared float tile_z[kTileHeight * kTileWidth];
shared uint tile_has_point;

// The tile position of border entry i: the top row, the bottom row, the left column, the right.
ivec2 border_position(int i) {
  if (i < kTileWidth) return ivec2(i, 0);
  if (i < 2 * kTileWidth) return ivec2(i - kTileWidth, kTileHeight - 1);
  const int j = i - 2 * kTileWidth;
  return j < RT_TILE_Y ? ivec2(0, j + 1) : ivec2(kTileWidth - 1, j - RT_TILE_Y + 1);
}

// The dispatch's camera's position in the site, which is not a constant: every camera's is read
// at a constant index and the view's kept by selection, before any branch (common/ibr_camera.glsl
// says why).
vec3 view_camera_position(int view) {
  vec3 chosen = cameras[0].site_from_camera[3].xyz;
  [[unroll]] for (int v = 1; v < RT_IBR_MAX_VIEWS; ++v)
    chosen = mix(chosen, cameras[v].site_from_camera[3].xyz, bvec3(view == v));
  return chosen;
}

void main() {
  int view = int(gl_GlobalInvocationID.z);
  vec3 camera_position = view_camera_position(view);
  ivec2 size = ivec2(lens_size(cameras[view].depth));
  int band = view * size.y;
  ivec2 origin = ivec2(gl_WorkGroupID.xy) * ivec2(RT_TILE_X, RT_TILE_Y) - 1;
  if (gl_LocalInvocationIndex == 0u) tile_has_point = 0u;
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  bool in_image = all(lessThan(pixel, size));  // no return: a barrier follows
  ivec2 local = ivec2(gl_LocalInvocationID.xy) + 1;
  vec4 centre = volume_point(pixel, band, size, camera_position);
  float z = centre.w;
  tile_z[local.y * kTileWidth + local.x] = z;
  for (int i = int(gl_LocalInvocationIndex); i < kBorder; i += RT_TILE_X * RT_TILE_Y) {
    ivec2 at = border_position(i);
    tile_z[at.y * kTileWidth + at.x] = volume_point(origin + at, band, size, camera_position).w;
  }
  barrier();

  int support = 0;
  if (z > 0.0)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        if (dx == 0 && dy == 0) continue;
        float neighbour = tile_z[(local.y + dy) * kTileWidth + local.x + dx];
        if (neighbour > 0.0 && abs(neighbour - z) <= edge_tolerance_m) ++support;
      }
  vec4 point = z > 0.0 && support >= min_support ? centre : vec4(0.0);
  if (in_image) {
    imageStore(points, ivec2(pixel.x, pixel.y + band), point);
    if (point.w > 0.0) atomicOr(tile_has_point, 1u);
  }
  barrier();
  if (gl_LocalInvocationIndex == 0u && tile_has_point != 0u)
    tiles[atomicAdd(tile_dispatch[0], 1u)] = uvec4(gl_WorkGroupID.xy, uint(view), 0u);
}
