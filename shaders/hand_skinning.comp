#version 460
#extension GL_GOOGLE_include_directive : require
// Paper Eq. 1, linear blend skinning: V'_i = sum_j w_ji T_j V_i, one invocation per vertex.
// Normals take the same blend of the bones' rotations (rigid T_j), renormalised.
#include "shared/config.h"

layout(local_size_x = 64) in;

layout(std430, binding = 0) readonly buffer RestVertices { HandVertex rest[]; };
layout(std430, binding = 1) readonly buffer BoneTransforms { mat4 bones[RT_HAND_BONES]; };
layout(std430, binding = 2) writeonly buffer Skinned { SkinnedVertex skinned[]; };
layout(push_constant) uniform Push { HandSkinParams params; };

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= params.vertex_count) return;
  HandVertex v = rest[i];
  mat4 blended = mat4(0.0);
  for (int k = 0; k < 4; ++k) {
    // Bone indices were checked at load; clamp anyway so a bad buffer cannot read out of range.
    int bone = clamp(int(v.joints[k] + 0.5), 0, RT_HAND_BONES - 1);
    blended += v.weights[k] * bones[bone];
  }
  vec3 position = (blended * vec4(v.position_u.xyz, 1.0)).xyz;
  vec3 normal = mat3(blended) * v.normal_v.xyz;
  normal = dot(normal, normal) > 1e-20 ? normalize(normal) : v.normal_v.xyz;
  skinned[i].position_u = vec4(position, v.position_u.w);
  skinned[i].normal_v = vec4(normal, v.normal_v.w);
}
