#version 460
#extension GL_GOOGLE_include_directive : require
// One convolution layer of Lumi-Net, its bias and activation fused: zero padding, stride 1, the
// same weights for every view (the views are the batch). One dispatch computes a group of
// RT_LUMI_CONV_GROUP output channels. Each workgroup stages its tile of the input, with the
// kernel's halo, in shared memory a chunk of channels at a time, so that each input value is read
// from the buffer once per workgroup rather than once per tap; every invocation then keeps its
// pixel's outputs in four vec4 accumulators. The group's weights come from a uniform buffer, laid
// out so that one tap's weights for the whole group are four consecutive vec4s: a CPU driver then
// loads them once for all the pixels it runs side by side, where from a storage buffer it loads
// them lane by lane, and it would keep an indexed array of sums in memory rather than registers.
#include "shared/config.h"
#include "shared/lumi_net.h"

layout(local_size_x = RT_TILE_X, local_size_y = RT_TILE_Y) in;
// Knobs, all set by LumiConvPass from LumiConvShape (passes/lumi_conv.h): the placeholders below
// are never used (a kernel refuses to build while one is unset).
layout(constant_id = 0) const int in_channels = 1;
layout(constant_id = 1) const int out_channels = 1;
layout(constant_id = 2) const int kernel_size = 1;  // 1 or 3
layout(constant_id = 3) const bool relu = false;

layout(std430, binding = 0) readonly buffer Source { float source[]; };
// The group's bias (four vec4s), then per input channel, row and column of the kernel the group's
// four vec4s of weights (passes/lumi_conv.h: lumi_conv_group_parameters); zeros past the layer's
// last output channel.
layout(std140, binding = 1) uniform Weights { vec4 weights[RT_LUMI_CONV_GROUP_VEC4S]; };
layout(std430, binding = 2) writeonly buffer Result { float result[]; };
layout(push_constant) uniform Push { LumiTensorParams params; };

const int radius = kernel_size / 2;
const int tile_w = RT_TILE_X + 2 * radius;
const int tile_h = RT_TILE_Y + 2 * radius;
// Sized for the largest kernel (3x3), so that the array's size is a plain constant.
shared float tile[RT_LUMI_CONV_CHANNEL_CHUNK * (RT_TILE_X + 2) * (RT_TILE_Y + 2)];

void store(int view, int o, ivec2 pixel, float value) {
  if (o >= out_channels) return;
  const int width = int(params.width), height = int(params.height);
  result[((view * out_channels + o) * height + pixel.y) * width + pixel.x] = relu ? max(value, 0.0) : value;
}

void main() {
  const int width = int(params.width), height = int(params.height);
  const int view = int(gl_WorkGroupID.z);
  const int first_out = int(params.first_output);
  const ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  const ivec2 local = ivec2(gl_LocalInvocationID.xy);
  const ivec2 origin = ivec2(gl_WorkGroupID.xy) * ivec2(RT_TILE_X, RT_TILE_Y) - radius;
  const bool inside = pixel.x < width && pixel.y < height;

  vec4 sum0 = weights[0], sum1 = weights[1], sum2 = weights[2], sum3 = weights[3];
  for (int first = 0; first < in_channels; first += RT_LUMI_CONV_CHANNEL_CHUNK) {
    const int chunk = min(RT_LUMI_CONV_CHANNEL_CHUNK, in_channels - first);
    barrier();  // every invocation is done reading the previous chunk
    for (int i = int(gl_LocalInvocationIndex); i < chunk * tile_w * tile_h; i += RT_TILE_X * RT_TILE_Y) {
      const int c = i / (tile_w * tile_h);
      const int rest = i - c * tile_w * tile_h;
      const ivec2 p = origin + ivec2(rest % tile_w, rest / tile_w);
      float value = 0.0;
      if (p.x >= 0 && p.y >= 0 && p.x < width && p.y < height)
        value = source[((view * in_channels + first + c) * height + p.y) * width + p.x];
      tile[i] = value;
    }
    barrier();
    // Invocations past the edge helped stage the tile; they compute nothing.
    if (!inside) continue;
    for (int c = 0; c < chunk; ++c)
      for (int ky = 0; ky < kernel_size; ++ky)
        for (int kx = 0; kx < kernel_size; ++kx) {
          const float value = tile[(c * tile_h + local.y + ky) * tile_w + local.x + kx];
          const int tap = 4 + 4 * (((first + c) * kernel_size + ky) * kernel_size + kx);
          // Only the accumulators the layer's outputs need: a head of two does not pay for sixteen.
          sum0 += weights[tap] * value;
          if (out_channels > 4) sum1 += weights[tap + 1] * value;
          if (out_channels > 8) sum2 += weights[tap + 2] * value;
          if (out_channels > 12) sum3 += weights[tap + 3] * value;
        }
  }
  if (!inside) return;
  for (int k = 0; k < 4; ++k) {
    store(view, first_out + k, pixel, sum0[k]);
    store(view, first_out + 4 + k, pixel, sum1[k]);
    store(view, first_out + 8 + k, pixel, sum2[k]);
    store(view, first_out + 12 + k, pixel, sum3[k]);
  }
}
