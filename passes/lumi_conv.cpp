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
  // The shader keeps every output channel of a pixel in registers.
  if (s.out_channels > 64) throw std::invalid_argument("lumi_conv: at most 64 output channels");
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

void LumiConvPass::add_to(vk::FrameGraph& graph, const std::string& name, vk::Buffer& source, vk::Buffer& parameters,
                          size_t weight_offset, vk::Buffer& result, uint32_t width, uint32_t height,
                          uint32_t views) const {
  const size_t pixels = size_t(width) * height * views;
  if (pixels == 0) throw std::invalid_argument("lumi_conv: empty tensor");
  check_size(source, pixels * shape_.in_channels, "the source tensor");
  check_size(result, pixels * shape_.out_channels, "the result tensor");
  check_size(parameters, weight_offset + shape_.parameter_count(), "the layer's parameters");
  graph.add_compute_pass({
      .name = name,
      .kernel = &kernel_,
      .bindings = {{"Source", &source}, {"Parameters", &parameters}, {"Result", &result}},
      .threads = {width, height, views},
      .push_constants = vk::push_constants_from<shader_abi::LumiTensorParams>([=] {
        return shader_abi::LumiTensorParams{width, height, views, uint32_t(weight_offset)};
      }),
  });
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
