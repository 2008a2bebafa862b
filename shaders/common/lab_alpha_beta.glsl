// Reinhard et al. 2001 L-alpha-beta, the GPU side of engine/hand/color_space.cpp (keep in step).
#ifndef REMOTETOUCH_LAB_ALPHA_BETA_GLSL
#define REMOTETOUCH_LAB_ALPHA_BETA_GLSL

// GLSL matrices are column-major: these are the transposes of the row-major tables.
const mat3 RGB_TO_LMS = mat3(0.3811, 0.1967, 0.0241, 0.5783, 0.7244, 0.1288, 0.0402, 0.0782, 0.8444);
const mat3 LMS_TO_RGB = mat3(4.4686699, -1.2197166, 0.0585085, -3.5886759, 2.3830879, -0.2610784, 0.1196044, -0.1626301,
                             1.2056659);  // the exact inverse
const float MIN_LMS = 1e-4;  // floor before log10: black stays finite

vec3 rgb_to_lab_alpha_beta(vec3 rgb) {
  vec3 lms = log(max(RGB_TO_LMS * rgb, vec3(MIN_LMS))) * 0.4342944819;  // log10
  return vec3((lms.x + lms.y + lms.z) * 0.5773502692, (lms.x + lms.y - 2.0 * lms.z) * 0.4082482905,
              (lms.x - lms.y) * 0.7071067812);
}

vec3 lab_alpha_beta_to_rgb(vec3 lab) {
  vec3 s = lab * vec3(0.5773502692, 0.4082482905, 0.7071067812);
  vec3 log_lms = vec3(s.x + s.y + s.z, s.x + s.y - s.z, s.x - 2.0 * s.y);
  // Clamped as in color_space.cpp: no transfer, however extreme, overflows.
  return LMS_TO_RGB * exp(clamp(log_lms, -4.0, 0.5) * 2.302585093);  // 10^x
}

#endif
