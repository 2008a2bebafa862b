#version 460
#extension GL_GOOGLE_include_directive : require
// A depth camera's depth registered into its colour camera: each measured surface is drawn into
// the colour image, the nearest surface wins, in millimetres along the colour camera's z.
//
// The surface is the mesh whose vertices are the depth pixels' centres: each invocation draws
// the cell between four neighbouring centres as two triangles (or the one triangle of three
// that lies on one surface). Neighbouring cells share their vertices, so a continuous surface
// covers the colour image without a crack however much larger the colour image is; squares
// around each depth pixel at its own depth would open cracks where the depth changes, as the
// baseline between the cameras moves near and far squares by different parallaxes. The price:
// outlines pull in by half a depth pixel, and a lone pixel with no neighbour on its surface
// draws nothing (on a time-of-flight camera these are mostly flying pixels).
//
// Two modes, one pass: `resolve` off splats into the buffer `nearest` (cleared to
// RT_DEPTH_IN_COLOR_EMPTY; one uint per colour pixel, since lavapipe has image atomics only on
// R32 formats, which we do not allocate); `resolve` on writes it out as 16-bit millimetres.
#include "shared/depth_in_color.h"
#include "common/lens.glsl"
#include "common/numeric.glsl"

layout(local_size_x = RT_TILE_X, local_size_y = RT_TILE_Y) in;
// Knobs, all set by DepthInColorPass from DepthInColorSettings (passes/depth_in_color.h), where
// their defaults live: the initial values are placeholders that GLSL requires, never used.
layout(constant_id = 0) const bool resolve = false;
layout(constant_id = 1) const float max_jump_m = 0.0;         // depth steps above this + relative * z
layout(constant_id = 2) const float max_jump_relative = 0.0;  // split surfaces
layout(constant_id = 3) const float max_triangle_px = 0.0;    // larger triangles are grazing or folded

layout(push_constant) uniform Push { DepthInColorParams params; };

layout(binding = 0, r16ui) uniform readonly uimage2D depth_mm;  // 0 = no measurement
// (x/z, y/z) of each depth pixel's ray, row by row (geometry/camera.h undistorted_pixel_rays).
layout(std430, binding = 1) readonly buffer Rays { vec2 rays[]; };
layout(std430, binding = 2) buffer Nearest { uint nearest[]; };  // colour pixels, row by row
layout(binding = 3, r16ui) uniform writeonly uimage2D depth_in_color;

struct Vertex {
  vec2 pixel;     // in the colour image, pixel centres at integers
  float color_z;  // metres
  float depth_z;  // metres, as the depth camera measured it
};

// The depth pixel's point in the colour image; false without a measurement, a ray, or a place
// in front of the colour camera within its lens's field.
bool vertex_at(ivec2 pixel, out Vertex v) {
  v = Vertex(vec2(0.0), 0.0, 0.0);
  uint millimetres = imageLoad(depth_mm, pixel).r;
  if (millimetres == 0u) return false;
  vec2 ray = rays[pixel.y * imageSize(depth_mm).x + pixel.x];
  if (!is_finite(ray.x) || !is_finite(ray.y)) return false;
  float z = float(millimetres) * 0.001;
  vec4 point = vec4(ray.x * z, ray.y * z, z, 1.0);
  vec3 c = vec3(dot(params.color_from_depth[0], point), dot(params.color_from_depth[1], point),
                dot(params.color_from_depth[2], point));
  if (!(c.z > RT_DEPTH_IN_COLOR_NEAR_M)) return false;
  vec2 xy = c.xy / c.z;
  // Beyond the field the rational model folds back and would land far points inside the image.
  if (!(dot(xy, xy) <= params.field.x)) return false;
  v.pixel = lens_pixel(params.color, xy);
  v.color_z = c.z;
  v.depth_z = z;
  return is_finite(v.pixel.x) && is_finite(v.pixel.y);
}

// Depths from `low` to `high` lie on one surface: within the jump allowed at the nearest.
bool one_surface(float low, float high) { return high - low <= max_jump_m + max_jump_relative * low; }

bool one_surface(Vertex a, Vertex b, Vertex c) {
  return one_surface(min(a.depth_z, min(b.depth_z, c.depth_z)), max(a.depth_z, max(b.depth_z, c.depth_z)));
}

// Every colour pixel centre in the triangle (edges included, with a hair of slack so that no
// centre on an edge two triangles share falls between them) takes the triangle's colour z there.
void splat_triangle(Vertex a, Vertex b, Vertex c) {
  float area = (b.pixel.x - a.pixel.x) * (c.pixel.y - a.pixel.y) - (b.pixel.y - a.pixel.y) * (c.pixel.x - a.pixel.x);
  if (!(abs(area) > 1e-12)) return;  // edge-on
  vec2 low = min(a.pixel, min(b.pixel, c.pixel)), high = max(a.pixel, max(b.pixel, c.pixel));
  if (any(greaterThan(high - low, vec2(max_triangle_px)))) return;
  ivec2 size = ivec2(params.color.tangential.zw);
  // Off the image: decided in floats, before anything converts to integers.
  if (any(lessThan(high, vec2(0.0))) || any(greaterThan(low, vec2(size - 1)))) return;
  // The box grows by a hair, as the edges do: a centre on a vertex must reach the edge test.
  ivec2 first = max(ivec2(ceil(low - 0.01)), ivec2(0)), last = min(ivec2(floor(high + 0.01)), size - 1);
  for (int y = first.y; y <= last.y; ++y)
    for (int x = first.x; x <= last.x; ++x) {
      vec2 p = vec2(x, y);
      float wa = ((b.pixel.x - p.x) * (c.pixel.y - p.y) - (b.pixel.y - p.y) * (c.pixel.x - p.x)) / area;
      float wb = ((c.pixel.x - p.x) * (a.pixel.y - p.y) - (c.pixel.y - p.y) * (a.pixel.x - p.x)) / area;
      float wc = 1.0 - wa - wb;
      if (wa < -1e-4 || wb < -1e-4 || wc < -1e-4) continue;
      float z = wa * a.color_z + wb * b.color_z + wc * c.color_z;
      // floor(x + 0.5), not round(): GLSL leaves the direction of halves to the driver.
      atomicMin(nearest[y * size.x + x], uint(clamp(floor(z * 1000.0 + 0.5), 1.0, 65535.0)));
    }
}

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (resolve) {
    ivec2 size = imageSize(depth_in_color);
    if (any(greaterThanEqual(pixel, size))) return;
    uint z = nearest[pixel.y * size.x + pixel.x];
    imageStore(depth_in_color, pixel, uvec4(z == RT_DEPTH_IN_COLOR_EMPTY ? 0u : z));
    return;
  }
  // One invocation per cell: the pixel and its neighbours to the right and below.
  if (any(greaterThanEqual(pixel + 1, imageSize(depth_mm)))) return;
  Vertex v00, v10, v01, v11;
  bool h00 = vertex_at(pixel, v00), h10 = vertex_at(pixel + ivec2(1, 0), v10);
  bool h01 = vertex_at(pixel + ivec2(0, 1), v01), h11 = vertex_at(pixel + ivec2(1, 1), v11);
  if (h00 && h10 && h01 && h11 &&
      one_surface(min(min(v00.depth_z, v10.depth_z), min(v01.depth_z, v11.depth_z)),
                  max(max(v00.depth_z, v10.depth_z), max(v01.depth_z, v11.depth_z)))) {
    splat_triangle(v00, v10, v11);
    splat_triangle(v00, v11, v01);
    return;
  }
  // Not one surface: each corner triangle that is (overlaps are harmless under the minimum).
  if (h00 && h10 && h01 && one_surface(v00, v10, v01)) splat_triangle(v00, v10, v01);
  if (h10 && h11 && h01 && one_surface(v10, v11, v01)) splat_triangle(v10, v11, v01);
  if (h00 && h10 && h11 && one_surface(v00, v10, v11)) splat_triangle(v00, v10, v11);
  if (h00 && h11 && h01 && one_surface(v00, v11, v01)) splat_triangle(v00, v11, v01);
}
