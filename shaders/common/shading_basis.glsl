// The geometry hand's shading basis (shared/hand_shading.h), the GPU side of hand/shading_fit.cpp
// (keep in step).
#ifndef REMOTETOUCH_SHADING_BASIS_GLSL
#define REMOTETOUCH_SHADING_BASIS_GLSL

void shading_basis(vec3 n, out float b[RT_SHADING_TERMS]) {
  b[0] = 1.0;
  b[1] = n.x;
  b[2] = n.y;
  b[3] = n.z;
  b[4] = n.x * n.y;
  b[5] = n.x * n.z;
  b[6] = n.y * n.z;
  b[7] = n.x * n.x - n.y * n.y;
  b[8] = 3.0 * n.z * n.z - 1.0;
}

#endif
