#include "ibr/lumi_net_model.h"

#include <array>
#include <cmath>
#include <cstring>
#include <fstream>
#include <stdexcept>

#include "config/assets.h"
#include "shared/lumi_net.h"

namespace rt::ibr {
namespace {

constexpr std::array<char, 8> kMagic = {'R', 'T', 'L', 'U', 'M', 'I', '0', '1'};

void check(const LumiNetShape& s) {
  if (s.channels == 0 || s.channels > 64 || s.blocks > 8 || s.scale == 0 || s.scale > 8)
    throw std::invalid_argument("Lumi-Net: channels must be 1-64, blocks 0-8 and scale 1-8");
}

}  // namespace

std::vector<LumiLayer> lumi_layers(const LumiNetShape& shape) {
  check(shape);
  std::vector<LumiLayer> layers;
  layers.push_back({"lumi_conv_in", RT_LUMI_INPUT_CHANNELS, shape.channels, 3, true, false});
  for (uint32_t b = 0; b < shape.blocks; ++b)
    layers.push_back({"lumi_conv_" + std::to_string(b + 1), 3 * shape.channels, shape.channels, 3, true, true});
  layers.push_back({"lumi_head", shape.channels, RT_LUMI_HEAD_CHANNELS, 1, false, false});
  size_t offset = 0;
  for (LumiLayer& layer : layers) {
    layer.offset = offset;
    offset += layer.parameter_count();
  }
  return layers;
}

size_t lumi_parameter_count(const LumiNetShape& shape) {
  const std::vector<LumiLayer> layers = lumi_layers(shape);
  return layers.back().offset + layers.back().parameter_count();
}

LumiNetModel random_lumi_net(const LumiNetShape& shape, uint32_t seed) {
  LumiNetModel model{shape, std::vector<float>(lumi_parameter_count(shape))};
  std::mt19937 rng(seed);
  for (const LumiLayer& layer : lumi_layers(shape)) {
    const float fan_in = float(layer.in_channels * layer.kernel_size * layer.kernel_size);
    std::normal_distribution<float> weight(0.0f, std::sqrt(2.0f / fan_in));
    std::uniform_real_distribution<float> bias(-0.1f, 0.1f);
    const size_t weights = layer.parameter_count() - layer.out_channels;
    for (size_t i = 0; i < weights; ++i) model.parameters[layer.offset + i] = weight(rng);
    for (size_t i = weights; i < layer.parameter_count(); ++i) model.parameters[layer.offset + i] = bias(rng);
  }
  return model;
}

LumiNetModel load_lumi_net(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot open Lumi-Net weights '" + path.string() + "' (scripts/train-lumi writes them)");
  std::array<char, 8> magic{};
  std::array<uint32_t, 5> header{};
  in.read(magic.data(), magic.size());
  in.read(reinterpret_cast<char*>(header.data()), sizeof(header));
  if (!in || magic != kMagic)
    throw std::runtime_error("'" + path.string() + "' is not a Lumi-Net weights file (no RTLUMI01 header)");
  if (header[0] != RT_LUMI_INPUT_CHANNELS)
    throw std::runtime_error("'" + path.string() + "' expects " + std::to_string(header[0]) + " input channels, the engine gives " +
                             std::to_string(RT_LUMI_INPUT_CHANNELS) + ": retrain with scripts/train-lumi");
  LumiNetModel model{{header[1], header[2], header[3]}, {}};
  check(model.shape);
  const size_t expected = lumi_parameter_count(model.shape);
  if (header[4] != expected)
    throw std::runtime_error("'" + path.string() + "' holds " + std::to_string(header[4]) + " parameters, its shape needs " +
                             std::to_string(expected));
  model.parameters.resize(expected);
  in.read(reinterpret_cast<char*>(model.parameters.data()), std::streamsize(expected * sizeof(float)));
  if (!in) throw std::runtime_error("'" + path.string() + "' is truncated");
  for (float p : model.parameters)
    if (!std::isfinite(p)) throw std::runtime_error("'" + path.string() + "' holds a NaN or Inf parameter");
  return model;
}

void save_lumi_net(const LumiNetModel& model, const std::filesystem::path& path) {
  if (model.parameters.size() != lumi_parameter_count(model.shape))
    throw std::invalid_argument("save_lumi_net: parameter count does not match the shape");
  std::ofstream out(path, std::ios::binary);
  const std::array<uint32_t, 5> header = {RT_LUMI_INPUT_CHANNELS, model.shape.channels, model.shape.blocks,
                                          model.shape.scale, uint32_t(model.parameters.size())};
  out.write(kMagic.data(), kMagic.size());
  out.write(reinterpret_cast<const char*>(header.data()), sizeof(header));
  out.write(reinterpret_cast<const char*>(model.parameters.data()), std::streamsize(model.parameters.size() * sizeof(float)));
  if (!out) throw std::runtime_error("cannot write '" + path.string() + "'");
}

std::filesystem::path default_lumi_net_path() { return config::assets_dir() / "lumi" / "lumi_net.bin"; }

}  // namespace rt::ibr
