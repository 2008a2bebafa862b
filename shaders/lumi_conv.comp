#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
// One convolution layer of Lumi-Net, its bias and activation fused: zero padding, stride 1, the
// same weights for every view (the views are the batch). One dispatch adds one chunk of at most
// RT_LUMI_CONV_CHANNEL_CHUNK input channels to a group of RT_LUMI_CONV_GROUP output channels: the
// first chunk starts from the bias, each later one from the sum the one before stored, and the
// last applies the activation. Each workgroup stages its tile of the chunk, with the kernel's
// halo, in shared memory, so that each input value is read from the buffer once per workgroup
// rather than once per tap. Every invocation computes RT_LUMI_CONV_PIXELS pixels of a row, each in
// four vec4 accumulators: each weight it loads feeds all of them, and a row's staged values are
// read once for all the taps that use them. The chunk's weights come from a uniform buffer of its
// own, laid out so that one tap's weights for the whole group are four consecutive vec4s. A CPU
// driver loads a uniform at a constant offset once for all lanes, but at an offset that depends on
// a loop counter lane by lane: the chunk's loops are unrolled so that every offset is a constant.
// A chunk bounds the straight-line code that makes: unrolled over a whole block layer's
// channels, it outgrew what the CPU runs fast.
#include "shared/config.h"
#include "shared/lumi_net.h"

layout(local_size_x = RT_TILE_X, local_size_y = RT_TILE_Y) in;
// Knobs, all set by LumiConvPass from LumiConvShape (passes/lumi_conv.h): the placeholders below
// are never used (a kernel refuses to build while one is unset).
layout(constant_id = 0) const int in_channels = 1;  // the layer's
layout(constant_id = 1) const int out_channels = 1;
layout(constant_id = 2) const int kernel_size = 1;  // 1 or 3
layout(constant_id = 3) const bool relu = false;    // set on the chunk that completes the sum
layout(constant_id = 4) const int chunk_channels = 1;  // the input channels this dispatch adds
layout(constant_id = 5) const bool accumulate = false;  // start from the stored sum, not the bias

layout(std430, binding = 0) readonly buffer Source { float source[]; };
// The group's bias (four vec4s), then per input channel of the chunk, row and column of the kernel
// the group's four vec4s of weights (passes/lumi_conv.h: lumi_conv_chunk_parameters); zeros past
// the layer's last output channel.
layout(std140, binding = 1) uniform Weights { vec4 weights[RT_LUMI_CONV_CHUNK_VEC4S]; };
layout(std430, binding = 2) buffer Result { float result[]; };
layout(push_constant) uniform Push { LumiTensorParams params; };

const int radius = kernel_size / 2;
// The vec4 accumulators of a pixel, and the vec4s of a tap's weights.
const int group_slots = RT_LUMI_CONV_GROUP / 4;
// ReLU's floor, or the lowest float: without an activation the sum is stored through a max all the
// same, a no-op on every finite value, because lavapipe ran a chunk that stored its sums plainly
// several times slower than one that stored them through a max.
const float floor_value = relu ? 0.0 : -3.4028235e38;
// Each invocation computes RT_LUMI_CONV_PIXELS neighbouring pixels of a row, so that each weight
// it loads feeds that many pixels and neighbouring taps share their staged values.
const int tile_w = RT_TILE_X * RT_LUMI_CONV_PIXELS + 2 * radius;
const int tile_h = RT_TILE_Y + 2 * radius;
// Sized for the largest kernel (3x3), so that the array's size is a plain constant.
// Staged in pairs of neighbouring values of a row: a CPU driver reads shared memory lane by lane,
// so a pair costs what one value did. An invocation's pixels and the kernel's halo are both even
// in number, so every row and every invocation's run of a row starts at a pair.
#if RT_LUMI_CONV_PIXELS % 2 != 0
#error "the staged pairs need an even number of pixels an invocation"
#endif
shared vec2 tile[RT_LUMI_CONV_CHANNEL_CHUNK * (RT_TILE_X * RT_LUMI_CONV_PIXELS + 2) * (RT_TILE_Y + 2) / 2];

bool stored(int o, ivec2 pixel) { return o < out_channels && pixel.x < int(params.width) && pixel.y < int(params.height); }
int result_index(int view, int o, ivec2 pixel) {
  return ((view * out_channels + o) * int(params.height) + pixel.y) * int(params.width) + pixel.x;
}

void main() {
  const int width = int(params.width), height = int(params.height);
  const int view = int(gl_WorkGroupID.z);
  const int first_out = int(params.first_output);
  const int first_in = int(params.first_input);
  const ivec2 local = ivec2(gl_LocalInvocationID.xy);
  const ivec2 origin = ivec2(gl_WorkGroupID.xy) * ivec2(RT_TILE_X * RT_LUMI_CONV_PIXELS, RT_TILE_Y) - radius;
  const ivec2 pixel = origin + radius + ivec2(local.x * RT_LUMI_CONV_PIXELS, local.y);
  const int group_vec4s = (out_channels + 3) / 4;  // a head of two needs one

  // Pixel p's outputs 4g to 4g+3 in sum[p * group_slots + g]. Invocations past the edge compute
  // on the tile's zero padding like the others (a branch here would not be jumped over on a CPU
  // driver, only add masking to every load) and store nothing.
  vec4 sum[RT_LUMI_CONV_PIXELS * group_slots];
  [[unroll]] for (int p = 0; p < RT_LUMI_CONV_PIXELS; ++p)
    [[unroll]] for (int g = 0; g < group_slots; ++g) {
      sum[p * group_slots + g] = weights[g];
      if (accumulate)
        [[unroll]] for (int k = 0; k < 4; ++k) {
          const int o = first_out + 4 * g + k;
          const ivec2 at = pixel + ivec2(p, 0);
          sum[p * group_slots + g][k] = stored(o, at) ? result[result_index(view, o, at)] : 0.0;
        }
    }
  for (int i = int(gl_LocalInvocationIndex); i < chunk_channels * tile_w * tile_h / 2; i += RT_TILE_X * RT_TILE_Y) {
    const int c = (2 * i) / (tile_w * tile_h);
    const int rest = 2 * i - c * tile_w * tile_h;
    const ivec2 p = origin + ivec2(rest % tile_w, rest / tile_w);
    const int at = ((view * in_channels + first_in + c) * height + p.y) * width + p.x;
    vec2 pair = vec2(0.0);
    if (p.y >= 0 && p.y < height) {
      if (p.x >= 0 && p.x < width) pair.x = source[at];
      if (p.x + 1 >= 0 && p.x + 1 < width) pair.y = source[at + 1];
    }
    tile[i] = pair;
  }
  barrier();
  [[unroll]] for (int c = 0; c < chunk_channels; ++c)
    [[unroll]] for (int ky = 0; ky < kernel_size; ++ky) {
      const int row = ((c * tile_h + local.y + ky) * tile_w + local.x * RT_LUMI_CONV_PIXELS) / 2;
      // The row's staged values the pixels' taps read, each read once, two at a time.
      float values[RT_LUMI_CONV_PIXELS + 2];
      [[unroll]] for (int x = 0; x < (RT_LUMI_CONV_PIXELS + 2 * radius) / 2; ++x) {
        const vec2 pair = tile[row + x];
        values[2 * x] = pair.x;
        values[2 * x + 1] = pair.y;
      }
      [[unroll]] for (int kx = 0; kx < kernel_size; ++kx) {
        const int tap = group_slots * (1 + (c * kernel_size + ky) * kernel_size + kx);
        // Only the accumulators the layer's outputs need: a head of two does not pay for sixteen.
        [[unroll]] for (int g = 0; g < group_slots; ++g) {
          if (g >= group_vec4s) break;
          const vec4 w = weights[tap + g];
          [[unroll]] for (int p = 0; p < RT_LUMI_CONV_PIXELS; ++p) sum[p * group_slots + g] += w * values[p + kx];
        }
      }
    }
  [[unroll]] for (int p = 0; p < RT_LUMI_CONV_PIXELS; ++p)
    [[unroll]] for (int k = 0; k < RT_LUMI_CONV_GROUP; ++k) {
      const int o = first_out + k;
      const ivec2 at = pixel + ivec2(p, 0);
      const float value = sum[p * group_slots + k / 4][k % 4];
      if (stored(o, at)) result[result_index(view, o, at)] = max(value, floor_value);
    }
}
