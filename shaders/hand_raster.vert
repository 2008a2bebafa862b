#version 460
#extension GL_GOOGLE_include_directive : require
// The skinned hand, indexed triangles pulled from storage buffers, seen from the target view.
#include "shared/config.h"

layout(std430, binding = 0) readonly buffer Skinned { SkinnedVertex skinned[]; };
layout(std430, binding = 1) readonly buffer Indices { uint indices[]; };
layout(push_constant) uniform Push { RasterViewParams view; };

layout(location = 0) out vec2 uv;
layout(location = 1) out float camera_z;

void main() {
  SkinnedVertex v = skinned[indices[gl_VertexIndex]];
  uv = vec2(v.position_u.w, v.normal_v.w);
  camera_z = dot(view.depth_row.xyz, v.position_u.xyz) + view.depth_row.w;
  gl_Position = view.clip_from_site * vec4(v.position_u.xyz, 1.0);
}
