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
// Input channels staged in shared memory per step of the 3x3 convolution: an 18x10 tile (two
// pixels an invocation) of 16 channels is 11.3 KiB, well inside the 32 KiB lavapipe offers, at any
// channel count.
#define RT_LUMI_CONV_CHANNEL_CHUNK 16
// Pixels of a row one invocation of the convolution computes: four ran no faster than two on lavapipe.
#define RT_LUMI_CONV_PIXELS 2
// Output channels one dispatch of the convolution computes, each invocation in four vec4
// accumulators: each staged input value then feeds this many multiply-adds.
#define RT_LUMI_CONV_GROUP 16
// The vec4s of a group's uniform buffer: 64 KiB, the uniform range NVIDIA's drivers and lavapipe
// offer. It holds the bias and the weights of 1023 taps (input channels times kernel taps).
#define RT_LUMI_CONV_GROUP_VEC4S 4096
// Logits above this count as this, so that +Inf still softmaxes to a finite one-hot weight.
#define RT_LUMI_MAX_LOGIT 1.0e4

// A tensor pass's size: the tensor's width and height, and the views (its batch).
struct LumiTensorParams {
  RT_LUMI_UINT width;
  RT_LUMI_UINT height;
  RT_LUMI_UINT views;
  RT_LUMI_UINT first_output;  // convolution only: the first output channel of the group a dispatch computes
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
