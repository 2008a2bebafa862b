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
  return s;
}

uint32_t chunk_channels(const LumiConvShape& s, uint32_t chunk) {
  return std::min<uint32_t>(RT_LUMI_CONV_CHANNEL_CHUNK, s.in_channels - chunk * RT_LUMI_CONV_CHANNEL_CHUNK);
}

std::unique_ptr<vk::ComputeKernel> make_kernel(vk::Context& context, const LumiConvShape& s, uint32_t chunk) {
  const bool last = chunk + 1 == lumi_conv_chunks(s);
  const std::vector<vk::Knob> knobs = {{"in_channels", int32_t(s.in_channels)},
                                       {"out_channels", int32_t(s.out_channels)},
                                       {"kernel_size", int32_t(s.kernel_size)},
                                       {"relu", s.relu && last},
                                       {"chunk_channels", int32_t(chunk_channels(s, chunk))},
                                       {"accumulate", chunk > 0}};
  return std::make_unique<vk::ComputeKernel>(context, "lumi_conv", lumi_conv_comp_spirv, knobs);
}

void check_size(const vk::Buffer& buffer, size_t floats, const std::string& what) {
  if (buffer.size() < floats * sizeof(float))
    throw std::invalid_argument("lumi_conv: '" + buffer.name() + "' holds fewer floats than " + what + " (" +
                                std::to_string(floats) + ")");
}

}  // namespace

LumiConvPass::LumiConvPass(vk::Context& context, const LumiConvShape& shape) : shape_(check(shape)) {
  const uint32_t chunks = lumi_conv_chunks(shape_);
  kernels_.push_back(make_kernel(context, shape_, 0));
  if (chunks > 2) kernels_.push_back(make_kernel(context, shape_, 1));
  if (chunks > 1) kernels_.push_back(make_kernel(context, shape_, chunks - 1));
}

const vk::ComputeKernel& LumiConvPass::chunk_kernel(uint32_t chunk) const {
  if (chunk == 0) return *kernels_.front();
  return chunk + 1 == lumi_conv_chunks(shape_) ? *kernels_.back() : *kernels_[1];
}

uint32_t lumi_conv_groups(const LumiConvShape& shape) {
  return (shape.out_channels + RT_LUMI_CONV_GROUP - 1) / RT_LUMI_CONV_GROUP;
}

uint32_t lumi_conv_chunks(const LumiConvShape& shape) {
  return (shape.in_channels + RT_LUMI_CONV_CHANNEL_CHUNK - 1) / RT_LUMI_CONV_CHANNEL_CHUNK;
}

std::vector<float> lumi_conv_chunk_parameters(std::span<const float> parameters, size_t weight_offset,
                                              const LumiConvShape& s, uint32_t group, uint32_t chunk) {
  check(s);
  if (parameters.size() < weight_offset + s.parameter_count())
    throw std::invalid_argument("lumi_conv: too few parameters for the layer");
  if (group >= lumi_conv_groups(s)) throw std::invalid_argument("lumi_conv: no such group of output channels");
  if (chunk >= lumi_conv_chunks(s)) throw std::invalid_argument("lumi_conv: no such chunk of input channels");
  const size_t kernel_taps = size_t(s.kernel_size) * s.kernel_size;
  const size_t taps = s.in_channels * kernel_taps;
  const size_t first_tap = size_t(chunk) * RT_LUMI_CONV_CHANNEL_CHUNK * kernel_taps;
  const size_t chunk_taps = chunk_channels(s, chunk) * kernel_taps;
  const float* weights = parameters.data() + weight_offset;
  const float* bias = weights + s.out_channels * taps;
  std::vector<float> packed((1 + chunk_taps) * RT_LUMI_CONV_GROUP, 0.0f);
  for (uint32_t k = 0; k < RT_LUMI_CONV_GROUP; ++k) {
    const uint32_t o = group * RT_LUMI_CONV_GROUP + k;
    if (o >= s.out_channels) break;
    packed[k] = bias[o];
    for (size_t tap = 0; tap < chunk_taps; ++tap)
      packed[(1 + tap) * RT_LUMI_CONV_GROUP + k] = weights[o * taps + first_tap + tap];
  }
  return packed;
}

LumiConvWeights LumiConvPass::upload_weights(vk::Context& context, std::span<const float> parameters,
                                             size_t weight_offset, const std::string& name) const {
  LumiConvWeights weights;
  for (uint32_t g = 0; g < lumi_conv_groups(shape_); ++g)
    for (uint32_t chunk = 0; chunk < lumi_conv_chunks(shape_); ++chunk) {
      const std::vector<float> packed = lumi_conv_chunk_parameters(parameters, weight_offset, shape_, g, chunk);
      const size_t bytes = packed.size() * sizeof(float);
      if (bytes > context.properties().limits.maxUniformBufferRange)
        throw std::runtime_error("lumi_conv: '" + name + "' needs a uniform buffer of " + std::to_string(bytes) +
                                 " bytes; the device offers " +
                                 std::to_string(context.properties().limits.maxUniformBufferRange));
      const std::string part = (g == 0 ? "" : " group " + std::to_string(g)) + (chunk == 0 ? "" : " chunk " + std::to_string(chunk));
      weights.chunks.emplace_back(context, vk::BufferDesc{name + part, bytes, VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT});
      vk::upload(context, weights.chunks.back(), std::as_bytes(std::span(packed)));
    }
  return weights;
}

void LumiConvPass::add_to(vk::FrameGraph& graph, const std::string& name, vk::Buffer& source, LumiConvWeights& weights,
                          vk::Buffer& result, uint32_t width, uint32_t height, uint32_t views) const {
  const size_t pixels = size_t(width) * height * views;
  if (pixels == 0) throw std::invalid_argument("lumi_conv: empty tensor");
  check_size(source, pixels * shape_.in_channels, "the source tensor");
  check_size(result, pixels * shape_.out_channels, "the result tensor");
  const uint32_t groups = lumi_conv_groups(shape_), chunks = lumi_conv_chunks(shape_);
  if (weights.chunks.size() != size_t(groups) * chunks)
    throw std::invalid_argument("lumi_conv: '" + name + "' has weights for " + std::to_string(weights.chunks.size()) +
                                " chunks of channels, the layer " + std::to_string(groups * chunks) + " (" +
                                std::to_string(groups) + " groups of outputs times " + std::to_string(chunks) +
                                " chunks of inputs)");
  for (uint32_t g = 0; g < groups; ++g)
    for (uint32_t chunk = 0; chunk < chunks; ++chunk) {
      const uint32_t first_output = g * RT_LUMI_CONV_GROUP, first_input = chunk * RT_LUMI_CONV_CHANNEL_CHUNK;
      std::string pass_name = name;
      if (g > 0) pass_name += " outputs " + std::to_string(first_output);
      if (chunk > 0) pass_name += " inputs " + std::to_string(first_input);
      graph.add_compute_pass({
          .name = pass_name,
          .kernel = &chunk_kernel(chunk),
          .bindings = {{"Source", &source}, {"Weights", &weights.chunks[size_t(g) * chunks + chunk]}, {"Result", &result}},
          .threads = {(width + RT_LUMI_CONV_PIXELS - 1) / RT_LUMI_CONV_PIXELS, height, views},
          .push_constants = vk::push_constants_from<shader_abi::LumiTensorParams>([=] {
            return shader_abi::LumiTensorParams{width, height, views, first_output, first_input};
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
