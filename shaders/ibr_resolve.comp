#version 460
#extension GL_GOOGLE_include_directive : require
// Resolves a portrait rendered at `factor` times the target's resolution to the target: each
// pixel's color and alpha are the box mean of its factor x factor samples, premultiplied (a
// sample nothing covers adds nothing), so silhouettes get the partial alpha a camera pixel has
// and sharp texture is filtered over the pixel instead of point-sampled; the color is stored
// straight again. The depth is the centre sample's (the truth's depth is a centre sample too),
// or where that is empty the nearest of the others, as the min-filter would keep.
#include "shared/config.h"
#include "common/numeric.glsl"

layout(local_size_x = RT_TILE_X, local_size_y = RT_TILE_Y) in;
// Knobs, all set by IbrResolvePass, from the factor it is given (passes/ibr_resolve.h), where their
// defaults live: a kernel refuses to build while one is unset, so the initial values below are
// placeholders that GLSL requires, never used.
layout(constant_id = 0) const int factor = 0;

layout(binding = 0, rgba32f) uniform readonly image2D fine_portrait;     // straight color, alpha
layout(binding = 1, r32f) uniform readonly image2D fine_depth;           // metres, 0 = nothing
layout(binding = 2, rgba32f) uniform writeonly image2D portrait;         // straight color, alpha
layout(binding = 3, r32f) uniform writeonly image2D portrait_depth;      // metres, 0 = nothing

void main() {
  ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  if (any(greaterThanEqual(pixel, imageSize(portrait)))) return;
  vec3 premultiplied = vec3(0.0);
  float coverage = 0.0, nearest = 0.0;
  for (int y = 0; y < factor; ++y)
    for (int x = 0; x < factor; ++x) {
      ivec2 fine = pixel * factor + ivec2(x, y);
      vec4 sample_color = imageLoad(fine_portrait, fine);
      // Written so that a NaN alpha counts as nothing.
      float alpha = sample_color.a > 0.0 ? min(sample_color.a, 1.0) : 0.0;
      premultiplied += unit_or_zero(sample_color.rgb) * alpha;
      coverage += alpha;
      float z = imageLoad(fine_depth, fine).r;
      if (is_finite(z) && z > 0.0 && (nearest == 0.0 || z < nearest)) nearest = z;
    }
  float centre = imageLoad(fine_depth, pixel * factor + ivec2(factor / 2)).r;
  if (is_finite(centre) && centre > 0.0) nearest = centre;
  vec3 color = coverage > 0.0 ? unit_or_zero(premultiplied / coverage) : vec3(0.0);
  imageStore(portrait, pixel, vec4(color, coverage / float(factor * factor)));
  imageStore(portrait_depth, pixel, vec4(nearest));
}
