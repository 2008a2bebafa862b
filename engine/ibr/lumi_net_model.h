#pragma once
// Lumi-Net as this project defines it (VirtualCube's exact architecture is not public; the README
// describes ours): its shape, its layers in order, and its parameters. A CPU module: the GPU
// forward pass is pipeline/lumi_net.h, the training scripts/train-lumi.
//
//   inputs (views, 7, H/s, W/s)  -> conv 3x3 7 -> C, ReLU
//   blocks times:                   pool (own, mean, max over seeing views) -> conv 3x3 3C -> C, ReLU
//   head:                           conv 1x1 C -> 2 (weight logit, alpha logit)
//   then a masked softmax over the views, bilinear upsampling by s, the blend.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

namespace rt::ibr {

struct LumiNetShape {
  uint32_t channels = 16;  // C: features per view and pixel
  uint32_t blocks = 2;     // pooled 3x3 layers after the first
  uint32_t scale = 2;      // the network runs at 1/scale of the target's resolution
};

struct LumiLayer {
  std::string name;  // e.g. "lumi_conv_in", names its pass in the frame graph
  uint32_t in_channels = 0, out_channels = 0, kernel_size = 3;
  bool relu = true;
  bool pooled_before = false;  // cross-view pooling feeds it (in_channels = 3 x the previous out)
  size_t offset = 0;           // its first float in the parameters: weights (out, in, ky, kx), bias
  size_t parameter_count() const { return size_t(out_channels) * in_channels * kernel_size * kernel_size + out_channels; }
};

std::vector<LumiLayer> lumi_layers(const LumiNetShape& shape);
size_t lumi_parameter_count(const LumiNetShape& shape);

struct LumiNetModel {
  LumiNetShape shape;
  std::vector<float> parameters;  // lumi_parameter_count(shape) floats, layer after layer
};

// He-initialised weights and small biases, for tests and as the training's starting point.
LumiNetModel random_lumi_net(const LumiNetShape& shape, uint32_t seed);

// The weights file (scripts/train-lumi writes it): "RTLUMI01", then little-endian uint32 input
// channels, channels, blocks, scale, parameter count, then the float32 parameters. Errors name
// the file and what is wrong.
LumiNetModel load_lumi_net(const std::filesystem::path& path);
void save_lumi_net(const LumiNetModel& model, const std::filesystem::path& path);

// assets/lumi/lumi_net.bin: the trained weights.
std::filesystem::path default_lumi_net_path();

}  // namespace rt::ibr
