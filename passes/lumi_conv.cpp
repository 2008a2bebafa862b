#include "passes/lumi_conv.h"

#include <algorithm>
#include <stdexcept>

#include "shared/lumi_net.h"

#include "lumi_conv.comp.h"

namespace rt::passes {
namespace {

const LumiConvShape& check(const LumiConvShape& s) {
  if (s.in_channels == 0 || s.out_channels == 0 || (s.kernel_size != 1 && s.kernel_size != 3))
    throw std::invalid_argument("lumi_conv: channel counts must be positive and the kernel 1x1 or 3x3");
  // A group's bias and weights fill at most one uniform buffer of the shader's size.
  const size_t taps = size_t(s.in_channels) * s.kernel_size * s.kernel_size;
  if ((1 + taps) * 4 > RT_LUMI_CONV_GROUP_VEC4S)
    throw std::invalid_argument("lumi_conv: " + std::to_string(s.in_channels) + " input channels of a " +
                                std::to_string(s.kernel_size) + "x" + std::to_string(s.kernel_size) +
                                " kernel are more weights than one uniform buffer holds (at most " +
                                std::to_string(RT_LUMI_CONV_GROUP_VEC4S / 4 - 1) + " input channels times taps)");
  return s;
}

void check_size(const vk::Buffer& buffer, size_t floats, const std::string& what) {
  if (buffer.size() < floats * sizeof(float))
    throw std::invalid_argument("lumi_conv: '" + buffer.name() + "' holds fewer floats than " + what + " (" +
                                std::to_string(floats) + ")");
}

}  // namespace

LumiConvPass::LumiConvPass(vk::Context& context, const LumiConvShape& shape)
    : shape_(check(shape)),
      kernel_(context, "lumi_conv", lumi_conv_comp_spirv,
              {{"in_channels", int32_t(shape.in_channels)},
               {"out_channels", int32_t(shape.out_channels)},
               {"kernel_size", int32_t(shape.kernel_size)},
               {"relu", shape.relu}}) {}

uint32_t lumi_conv_groups(const LumiConvShape& shape) {
  return (shape.out_channels + RT_LUMI_CONV_GROUP - 1) / RT_LUMI_CONV_GROUP;
}

std::vector<float> lumi_conv_group_parameters(std::span<const float> parameters, size_t weight_offset,
                                              const LumiConvShape& s, uint32_t group) {
  check(s);
  if (parameters.size() < weight_offset + s.parameter_count())
    throw std::invalid_argument("lumi_conv: too few parameters for the layer");
  if (group >= lumi_conv_groups(s)) throw std::invalid_argument("lumi_conv: no such group of output channels");
  const size_t taps = size_t(s.in_channels) * s.kernel_size * s.kernel_size;
  const float* weights = parameters.data() + weight_offset;
  const float* bias = weights + s.out_channels * taps;
  std::vector<float> packed((1 + taps) * RT_LUMI_CONV_GROUP, 0.0f);
  for (uint32_t k = 0; k < RT_LUMI_CONV_GROUP; ++k) {
    const uint32_t o = group * RT_LUMI_CONV_GROUP + k;
    if (o >= s.out_channels) break;
    packed[k] = bias[o];
    for (size_t tap = 0; tap < taps; ++tap) packed[(1 + tap) * RT_LUMI_CONV_GROUP + k] = weights[o * taps + tap];
  }
  return packed;
}

LumiConvWeights LumiConvPass::upload_weights(vk::Context& context, std::span<const float> parameters,
                                             size_t weight_offset, const std::string& name) const {
  LumiConvWeights weights;
  for (uint32_t g = 0; g < lumi_conv_groups(shape_); ++g) {
    const std::vector<float> packed = lumi_conv_group_parameters(parameters, weight_offset, shape_, g);
    const size_t bytes = packed.size() * sizeof(float);
    if (bytes > context.properties().limits.maxUniformBufferRange)
      throw std::runtime_error("lumi_conv: '" + name + "' needs a uniform buffer of " + std::to_string(bytes) +
                               " bytes; the device offers " +
                               std::to_string(context.properties().limits.maxUniformBufferRange));
    weights.groups.emplace_back(context, vk::BufferDesc{name + (g == 0 ? "" : " group " + std::to_string(g)), bytes,
                                                        VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT});
    vk::upload(context, weights.groups.back(), std::as_bytes(std::span(packed)));
  }
  return weights;
}

void LumiConvPass::add_to(vk::FrameGraph& graph, const std::string& name, vk::Buffer& source, LumiConvWeights& weights,
                          vk::Buffer& result, uint32_t width, uint32_t height, uint32_t views) const {
  const size_t pixels = size_t(width) * height * views;
  if (pixels == 0) throw std::invalid_argument("lumi_conv: empty tensor");
  check_size(source, pixels * shape_.in_channels, "the source tensor");
  check_size(result, pixels * shape_.out_channels, "the result tensor");
  if (weights.groups.size() != lumi_conv_groups(shape_))
    throw std::invalid_argument("lumi_conv: '" + name + "' has weights for " + std::to_string(weights.groups.size()) +
                                " groups of output channels, the layer " + std::to_string(lumi_conv_groups(shape_)));
  for (uint32_t g = 0; g < weights.groups.size(); ++g) {
    const uint32_t first_output = g * RT_LUMI_CONV_GROUP;
    graph.add_compute_pass({
        .name = g == 0 ? name : name + " outputs " + std::to_string(first_output),
        .kernel = &kernel_,
        .bindings = {{"Source", &source}, {"Weights", &weights.groups[g]}, {"Result", &result}},
        .threads = {(width + RT_LUMI_CONV_PIXELS - 1) / RT_LUMI_CONV_PIXELS, height, views},
        .push_constants = vk::push_constants_from<shader_abi::LumiTensorParams>([=] {
          return shader_abi::LumiTensorParams{width, height, views, first_output};
        }),
    });
  }
}

LumiTensor lumi_conv_reference(const LumiTensor& source, std::span<const float> parameters, size_t weight_offset,
                               const LumiConvShape& s) {
  check(s);
  if (source.channels != s.in_channels) throw std::invalid_argument("lumi_conv_reference: channel count differs");
  if (parameters.size() < weight_offset + s.parameter_count())
    throw std::invalid_argument("lumi_conv_reference: too few parameters");
  const int k = int(s.kernel_size), r = k / 2, w = int(source.width), h = int(source.height);
  const float* weights = parameters.data() + weight_offset;
  const float* bias = weights + size_t(s.out_channels) * s.in_channels * k * k;
  LumiTensor out(source.views, s.out_channels, source.width, source.height);
  for (uint32_t v = 0; v < source.views; ++v)
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        for (uint32_t o = 0; o < s.out_channels; ++o) {
          // The shader's order of summation: bias, then input channel, row, column.
          float sum = bias[o];
          for (uint32_t c = 0; c < s.in_channels; ++c)
            for (int ky = 0; ky < k; ++ky)
              for (int kx = 0; kx < k; ++kx) {
                const int sx = x + kx - r, sy = y + ky - r;
                const float value = sx >= 0 && sy >= 0 && sx < w && sy < h ? source.at(v, c, uint32_t(sx), uint32_t(sy)) : 0.0f;
                sum += weights[((size_t(o) * s.in_channels + c) * k + ky) * k + kx] * value;
              }
          out.at(v, o, uint32_t(x), uint32_t(y)) = s.relu ? std::max(sum, 0.0f) : sum;
        }
  return out;
}

}  // namespace rt::passes
