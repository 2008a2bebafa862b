#version 460
#extension GL_GOOGLE_include_directive : require
// The skinned hand, indexed triangles pulled from storage buffers, seen from the target view.
#include "shared/config.h"
#include "shared/hand_shading.h"

layout(std430, binding = 0) readonly buffer Skinned { SkinnedVertex skinned[]; };
layout(std430, binding = 1) readonly buffer Indices { uint indices[]; };
layout(push_constant) uniform Push { HandRasterParams params; };

layout(location = 0) out vec2 uv;
layout(location = 1) out float camera_z;
layout(location = 2) out vec3 site_normal;

void main() {
  SkinnedVertex v = skinned[indices[gl_VertexIndex]];
  uv = vec2(v.position_u.w, v.normal_v.w);
  camera_z = dot(params.view.depth_row.xyz, v.position_u.xyz) + params.view.depth_row.w;
  site_normal = v.normal_v.xyz;
  gl_Position = params.view.clip_from_site * vec4(v.position_u.xyz, 1.0);
}
