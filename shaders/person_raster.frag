#version 460
#extension GL_GOOGLE_include_directive : require
// Unlit albedo with a fixed, view-independent shading term, so that every camera sees the same
// color at a surface point (what image-based rendering assumes), plus the stripes on clothing
// that make blending errors visible, and the face photograph on the front of the head, so that
// the viewer's eyes can be found in the cameras. Also writes the camera's linear depth and the
// part mask.
#include "shared/config.h"

// A negative stripe period marks the head: stripe.xy is then where the vertex lies on the face
// texture and stripe.z how squarely it faces forward (1 on the face, 0 from the sides back), so
// that the planar projection does not print the face again on the back of the head. The face
// texture holds the photograph relative to its skin (rgb) and where it replaces the skin (a).
layout(binding = 1) uniform sampler2D face_texture;

layout(location = 0) in vec3 site_position;
layout(location = 1) in vec3 normal;
layout(location = 2) in vec4 albedo;
layout(location = 3) in vec4 stripe;
layout(location = 4) in float camera_z;
layout(location = 5) flat in float part;

layout(location = 0) out vec4 out_color;    // rgba8
layout(location = 1) out float out_depth_m; // r32f, 0 = nothing there (the clear value)
layout(location = 2) out float out_part;    // r32f, RT_PART_*

const vec3 light_direction = vec3(0.2672612, 0.5345225, 0.8017837);  // normalize(1, 2, 3)

void main() {
  vec3 base = albedo.rgb;
  if (stripe.w < 0.0) {
    vec4 face = texture(face_texture, stripe.xy);
    base = mix(base, base * face.rgb, face.a * clamp(stripe.z, 0.0, 1.0));
  } else if (stripe.w > 0.0 && fract(site_position.y / stripe.w) >= 0.5) {
    base = stripe.rgb;
  }
  // Two-sided: a normal's sign depends on how the mesh was wound.
  vec3 unit_normal = dot(normal, normal) > 1e-12 ? normalize(normal) : light_direction;  // degenerate: lit
  float shade = 0.35 + 0.65 * abs(dot(unit_normal, light_direction));
  out_color = vec4(base * shade, 1.0);
  out_depth_m = camera_z;
  out_part = part;
}
