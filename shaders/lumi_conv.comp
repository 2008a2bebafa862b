#version 460
#extension GL_GOOGLE_include_directive : require
// One convolution layer of Lumi-Net, its bias and activation fused: zero padding, stride 1, the
// same weights for every view (the views are the batch). Each workgroup stages its tile of the
// input, with the kernel's halo, in shared memory a chunk of channels at a time, so that each
// input value is read from the buffer once per workgroup rather than once per tap; every
// invocation then keeps all output channels of its pixel in registers.
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
// Weights as PyTorch stores them (out, in, ky, kx), then the bias (out), from weight_offset.
layout(std430, binding = 1) readonly buffer Parameters { float parameters[]; };
layout(std430, binding = 2) writeonly buffer Result { float result[]; };
layout(push_constant) uniform Push { LumiTensorParams params; };

const int radius = kernel_size / 2;
const int tile_w = RT_TILE_X + 2 * radius;
const int tile_h = RT_TILE_Y + 2 * radius;
// Sized for the largest kernel (3x3), so that the array's size is a plain constant.
shared float tile[RT_LUMI_CONV_CHANNEL_CHUNK * (RT_TILE_X + 2) * (RT_TILE_Y + 2)];

void main() {
  const int width = int(params.width), height = int(params.height);
  const int view = int(gl_WorkGroupID.z);
  const ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
  const ivec2 local = ivec2(gl_LocalInvocationID.xy);
  const ivec2 origin = ivec2(gl_WorkGroupID.xy) * ivec2(RT_TILE_X, RT_TILE_Y) - radius;
  const bool inside = pixel.x < width && pixel.y < height;
  const int taps = kernel_size * kernel_size;
  const uint bias_offset = params.weight_offset + uint(out_channels * in_channels * taps);

  float sum[out_channels];
  for (int o = 0; o < out_channels; ++o) sum[o] = parameters[bias_offset + uint(o)];

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
          const uint tap = params.weight_offset + uint(((first + c) * kernel_size + ky) * kernel_size + kx);
          for (int o = 0; o < out_channels; ++o)
            sum[o] += parameters[tap + uint(o * in_channels * taps)] * value;
        }
  }
  if (!inside) return;
  for (int o = 0; o < out_channels; ++o)
    result[((view * out_channels + o) * height + pixel.y) * width + pixel.x] = relu ? max(sum[o], 0.0) : sum[o];
}
