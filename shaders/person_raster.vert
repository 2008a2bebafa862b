#version 460
#extension GL_GOOGLE_include_directive : require
// Simulated people and hands: triangles pulled from a storage buffer, seen from one camera.
#include "shared/config.h"

layout(std430, binding = 0) readonly buffer Mesh { MeshVertex vertices[]; };
layout(push_constant) uniform Push { RasterViewParams view; };

layout(location = 0) out vec3 site_position;
layout(location = 1) out vec3 normal;
layout(location = 2) out vec4 albedo;
layout(location = 3) out vec4 stripe;  // rgb: stripe albedo, w: period (0 = plain, < 0 = the face: person_raster.frag)
layout(location = 4) out float camera_z;
layout(location = 5) flat out float part;

void main() {
  MeshVertex v = vertices[gl_VertexIndex];
  site_position = v.position_part.xyz;
  normal = v.normal_stripe.xyz;
  albedo = v.color;
  stripe = vec4(v.stripe_color.rgb, v.normal_stripe.w);
  camera_z = dot(view.depth_row.xyz, site_position) + view.depth_row.w;
  part = v.position_part.w;
  gl_Position = view.clip_from_site * vec4(site_position, 1.0);
}
