// Shared by GLSL and C++: the push-constant blocks of the Lumi-Net passes (passes/lumi_*).
// Kept out of config.h so that the network's ABI can change without rebuilding every pass.
// Only 4-byte scalars, so that GLSL's std430 layout and C++'s agree by construction.
//
// Tensors are storage buffers of floats in the layout PyTorch and ONNX call NCHW, with the views
// as the batch: value (view v, channel c, row y, column x) at ((v * C + c) * height + y) * width + x.
#ifndef REMOTETOUCH_SHADER_LUMI_NET_H
#define REMOTETOUCH_SHADER_LUMI_NET_H

#ifdef __cplusplus
#include <cstdint>
#define RT_LUMI_UINT std::uint32_t
namespace rt::shader_abi {
#else
#define RT_LUMI_UINT uint
#endif

// Channels of the network's input per view and pixel (passes/lumi_input.h lists them).
#define RT_LUMI_INPUT_CHANNELS 7
// The head's outputs per view and pixel: the view's weight logit and its alpha logit.
#define RT_LUMI_HEAD_CHANNELS 2
// Input channels one dispatch of the convolution adds, staged in shared memory: an 18x10 tile (two
// pixels an invocation) of 16 channels is 11.3 KiB, well inside the 32 KiB lavapipe offers. The
// dispatch's loops over them are unrolled: on lavapipe that ran fast up to this many channels of
// a 3x3 kernel, and slower than the loops at twice as many.
#define RT_LUMI_CONV_CHANNEL_CHUNK 16
// Pixels of a row one invocation of the convolution computes: four ran no faster than two on lavapipe.
#define RT_LUMI_CONV_PIXELS 2
// Output channels one dispatch of the convolution computes, each invocation in four vec4
// accumulators: each staged input value then feeds this many multiply-adds.
#define RT_LUMI_CONV_GROUP 16
// The vec4s of a chunk's uniform buffer: the bias and the weights of a chunk of a 3x3 kernel.
#define RT_LUMI_CONV_CHUNK_VEC4S (RT_LUMI_CONV_GROUP / 4 * (1 + RT_LUMI_CONV_CHANNEL_CHUNK * 9))
// Logits above this count as this, so that +Inf still softmaxes to a finite one-hot weight.
#define RT_LUMI_MAX_LOGIT 1.0e4

// A tensor pass's size: the tensor's width and height, and the views (its batch).
struct LumiTensorParams {
  RT_LUMI_UINT width;
  RT_LUMI_UINT height;
  RT_LUMI_UINT views;
  RT_LUMI_UINT first_output;  // convolution only: the first output channel of the group a dispatch computes
  RT_LUMI_UINT first_input;   // convolution only: the first input channel of the chunk a dispatch adds
};

// A pass between the target's full resolution and the network's reduced one.
struct LumiScaleParams {
  RT_LUMI_UINT width;          // full resolution
  RT_LUMI_UINT height;
  RT_LUMI_UINT small_width;    // the network's: ceil(width / scale)
  RT_LUMI_UINT small_height;
  RT_LUMI_UINT views;
  RT_LUMI_UINT scale;
};

#ifdef __cplusplus
}  // namespace rt::shader_abi
#endif
#undef RT_LUMI_UINT
#endif
