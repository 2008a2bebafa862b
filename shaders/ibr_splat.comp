#version 460
#extension GL_GOOGLE_include_directive : require
// Depth reprojection (paper 3.1.1): every foreground point of every view is projected into the
// target view and splatted over the pixels its depth pixel covers there. The fused depth keeps
// the nearest surface, the paper's min-filter: positive floats order as their bit patterns, so a
// 32-bit atomicMin on the bits is a depth test with no race. With `accumulate_average` the pass
// instead sums the depths that agree with that minimum, for the averaging baseline (run after
// the min pass).
#include "shared/config.h"
#include "common/ibr_camera.glsl"
#include "common/numeric.glsl"

layout(local_size_x = RT_TILE_X, local_size_y = RT_TILE_Y) in;
// Knobs, all set by IbrSplatPass, from SplatSettings (passes/ibr_splat.h), where their defaults
// live: a kernel refuses to build while one is unset, so the initial values below are placeholders
// that GLSL requires, never used.
layout(constant_id = 0) const bool accumulate_average = false;
layout(constant_id = 1) const float footprint_scale = 0.0;   // splat side over the projected pixel size
layout(constant_id = 2) const float max_footprint_px = 0.0;
layout(constant_id = 3) const float average_tolerance_m = 0.0;  // depths this far behind the nearest join its average
layout(constant_id = 4) const float plane_tolerance_m = 0.0;    // neighbours this close span the splat's plane
layout(constant_id = 5) const float edge_inset = 0.0;           // of a depth pixel, on sides without a neighbour

layout(binding = 0, rgba32f) uniform readonly image2D points;  // site xyz, camera z; 0 = none
// [0, n): nearest depth bits; [n, 2n): sum of agreeing depths (10 micrometre units); [2n, 3n): their count.
layout(std430, binding = 1) buffer Fusion { uint fusion[]; };
// The tiles of the points atlas that hold a point (ibr_foreground): one workgroup each, as on
// llvmpipe a tile without one would cost as much as one with (see ibr_tiles.comp).
layout(std430, binding = 2) readonly buffer Tiles { uvec4 tiles[]; };  // column, row, view, 0

// Where a foreground point lands in the target view: (pixel x, pixel y, camera z); false when
// it is missing, behind the eye or far outside the image.
bool project_point(IbrTarget eye_view, ivec2 pixel, int view, ivec2 size, out vec3 projected) {
  projected = vec3(0.0);
  if (any(lessThan(pixel, ivec2(0))) || any(greaterThanEqual(pixel, size))) return false;
  vec4 point = imageLoad(points, ivec2(pixel.x, pixel.y + view * size.y));
  if (point.w <= 0.0) return false;
  vec3 p = transform_point(eye_view.camera_from_site, point.xyz);
  if (p.z <= 1e-4) return false;
  projected = vec3(eye_view.pinhole.xy * (p.xy / p.z) + eye_view.pinhole.zw, p.z);
  return is_finite(projected.x) && is_finite(projected.y);
}

// The neighbour at `neighbour` when it lies on the same surface as `centre`: its offset from
// `centre` in target pixels and depth.
bool surface_neighbour(IbrTarget eye_view, ivec2 neighbour, int view, ivec2 size, vec3 centre, out vec3 offset) {
  vec3 q;
  offset = vec3(0.0);
  if (!project_point(eye_view, neighbour, view, size, q) || abs(q.z - centre.z) > plane_tolerance_m) return false;
  offset = q - centre;
  return true;
}

// Two steps across the surface span an area as the eye sees them (not edge-on).
bool spans_area(vec3 u, vec3 v) {
  float det = u.x * v.y - u.y * v.x;
  return abs(det) > 0.01 * length(u.xy) * length(v.xy) && abs(det) > 1e-8;
}

// The depth at `offset` (target pixels from the splat's centre at depth `z0`) on the first
// quarter that holds it: offset = a * x_step + b * y_step with 0 <= a, b <= the sides' limits
// (right, left, below, above); false when none does.
bool quarter_depth(vec2 offset, float z0, vec3 step_right, vec3 step_left, vec3 step_below, vec3 step_above,
                   vec4 side_limit, out float z) {
  z = z0;
  for (int quarter = 0; quarter < 4; ++quarter) {
    bool to_x_left = (quarter & 1) != 0, to_y_above = (quarter & 2) != 0;
    vec3 x_step = to_x_left ? step_left : step_right;
    vec3 y_step = to_y_above ? step_above : step_below;
    if (!spans_area(x_step, y_step)) continue;
    float det = x_step.x * y_step.y - x_step.y * y_step.x;
    float a = (offset.x * y_step.y - offset.y * y_step.x) / det;
    float b = (x_step.x * offset.y - x_step.y * offset.x) / det;
    float a_limit = to_x_left ? side_limit.y : side_limit.x;
    float b_limit = to_y_above ? side_limit.w : side_limit.z;
    // The small negative slack keeps pixels on a shared border from falling between quarters.
    if (a < -1e-4 || b < -1e-4 || a > a_limit || b > b_limit) continue;
    z = max(z0 + a * x_step.z + b * y_step.z, 1e-4);
    return true;
  }
  return false;
}

void main() {
  IbrTarget eye_view = target;  // read before the first branch (common/ibr_camera.glsl says why)
  uvec4 listed = tiles[gl_WorkGroupID.x];
  int view = int(listed.z);
  ivec2 size = ivec2(lens_size(cameras[view].depth));
  ivec2 pixel = ivec2(listed.xy * uvec2(RT_TILE_X, RT_TILE_Y) + gl_LocalInvocationID.xy);
  if (any(greaterThanEqual(pixel, size))) return;
  vec4 point = imageLoad(points, ivec2(pixel.x, pixel.y + view * size.y));
  if (point.w <= 0.0) return;
  vec3 p = transform_point(eye_view.camera_from_site, point.xyz);
  if (p.z <= 1e-4) return;  // behind the eye: not in the target view
  vec2 centre = eye_view.pinhole.xy * (p.xy / p.z) + eye_view.pinhole.zw;
  // Far outside the image (grazing the eye plane): skip before converting to integers.
  if (!is_finite(centre.x) || !is_finite(centre.y)) return;
  if (any(lessThan(centre, vec2(-max_footprint_px))) || any(greaterThan(centre, eye_view.size.xy + max_footprint_px))) return;
  // The splat is the depth pixel's own piece of the surface: the four quarters between it and
  // its neighbours in the depth image, half-way to each, each quarter on the plane through the
  // point and the two neighbours that bound it. Neighbouring splats of one surface then tile the
  // target without overlapping or spilling past a silhouette, whatever the angles of the camera
  // and the eye to the surface, and their depths agree instead of the min-filter picking the
  // front step of a staircase. One plane for the whole splat would extrapolate half of it from
  // the far side's neighbours: on a curved surface (a finger) that lies in front of the surface,
  // steeply so where the eye grazes it, and the min-filter keeps exactly those errors.
  vec3 here = vec3(centre, p.z);
  vec3 to_right, to_left, to_below, to_above;
  bool right = surface_neighbour(eye_view, pixel + ivec2(1, 0), view, size, here, to_right);
  bool left = surface_neighbour(eye_view, pixel - ivec2(1, 0), view, size, here, to_left);
  bool below = surface_neighbour(eye_view, pixel + ivec2(0, 1), view, size, here, to_below);
  bool above = surface_neighbour(eye_view, pixel - ivec2(0, 1), view, size, here, to_above);
  // One step each way along each axis of the depth image; a side without its neighbour mirrors
  // the other side's step (the surface continued, up to where it ends).
  vec3 step_right = right ? to_right : -to_left, step_left = left ? to_left : -to_right;
  vec3 step_below = below ? to_below : -to_above, step_above = above ? to_above : -to_below;
  bool on_surface = (right || left) && (below || above) && spans_area(step_right, step_below);
  vec2 half_extent;
  if (on_surface) {
    half_extent = min(0.5 * footprint_scale * (max(abs(step_right.xy), abs(step_left.xy)) +
                                               max(abs(step_below.xy), abs(step_above.xy))),
                      vec2(0.5 * max_footprint_px));
  } else {
    // No surface around it (an edge, a thin finger): a square of the depth pixel's width at
    // its depth (point.w / fx_depth metres) as the eye sees it, at least a pixel, at one depth.
    // Not inset: which side of the square faces the missing neighbour is not known, and shrinking
    // all of it would break a thin line of squares (a finger a depth pixel wide) into dots.
    float footprint = footprint_scale * (point.w / cameras[view].depth.pinhole.x) * eye_view.pinhole.x / p.z;
    half_extent = vec2(0.5 * clamp(footprint, 1.0, max_footprint_px));
  }
  ivec2 target_size = ivec2(eye_view.size.xy);
  ivec2 first = max(ivec2(ceil(centre - half_extent)), ivec2(0));
  ivec2 last = min(ivec2(floor(centre + half_extent)), target_size - 1);
  float patch_limit = 0.5 * footprint_scale + 1e-3;  // a hair over half-way: no cracks between neighbours
  // Each side that ends the surface (an outline, a depth edge) pulls in by edge_inset: the
  // min-filter keeps the union of the views' splats, so otherwise every outline grows by the
  // largest of the views' half-pixel errors (about 0.5 - 1 / (k + 1) depth pixels for k views).
  vec4 side_limit = patch_limit - edge_inset * vec4(right ? 0.0 : 1.0, left ? 0.0 : 1.0, below ? 0.0 : 1.0,
                                                    above ? 0.0 : 1.0);
  uint n = uint(target_size.x * target_size.y);
  for (int y = first.y; y <= last.y; ++y)
    for (int x = first.x; x <= last.x; ++x) {
      float z = p.z;
      if (on_surface) {
        vec2 offset = vec2(x, y) - centre;
        if (!quarter_depth(offset, p.z, step_right, step_left, step_below, step_above, side_limit, z)) continue;
      }
      uint index = uint(y * target_size.x + x);
      if (!accumulate_average) {
        atomicMin(fusion[index], floatBitsToUint(z));
      } else if (z <= uintBitsToFloat(fusion[index]) + average_tolerance_m) {
        atomicAdd(fusion[n + index], uint(floor(z * 1e5 + 0.5)));
        atomicAdd(fusion[2u * n + index], 1u);
      }
    }
}
