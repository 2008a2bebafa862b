#include "support/pass_harness.h"

#include <stdexcept>

#include "support/gpu_test.h"

namespace rt::test {
namespace {

template <typename Map>
std::string names_in(const Map& map) {
  std::string names;
  for (const auto& [name, value] : map) names += (names.empty() ? "'" : ", '") + name + "'";
  return names.empty() ? "none" : names;
}

}  // namespace

const HostImage& PassOutputs::image(const std::string& name) const {
  const auto found = images_.find(name);
  if (found == images_.end())
    throw std::invalid_argument("no image output '" + name + "' (the outputs: " + names_in(images_) + ")");
  return found->second;
}

const std::vector<std::byte>& PassOutputs::bytes(const std::string& name) const {
  const auto found = buffers_.find(name);
  if (found == buffers_.end())
    throw std::invalid_argument("no buffer output '" + name + "' (the outputs: " + names_in(buffers_) + ")");
  return found->second;
}

void PassOutputs::check_whole(const std::string& name, size_t bytes, size_t value_size) {
  if (bytes % value_size != 0)
    throw std::invalid_argument("buffer output '" + name + "' holds " + std::to_string(bytes) +
                                " bytes, not a whole number of " + std::to_string(value_size) + "-byte values");
}

void PassOutputs::check_single(const std::string& name, size_t count) {
  if (count != 1)
    throw std::invalid_argument("buffer output '" + name + "' holds " + std::to_string(count) + " values, not one");
}

PassHarness::PassHarness(const std::string& name) : context_(gpu()), name_(name) {}

PassHarness::~PassHarness() = default;

vk::FrameGraph& PassHarness::graph() {
  if (ran_) throw std::logic_error("pass harness '" + name_ + "' has already run");
  if (!graph_) graph_ = std::make_unique<vk::FrameGraph>(context_, "test " + name_);
  return *graph_;
}

void PassHarness::check_new(const std::string& name) const {
  if (images_.count(name) || buffers_.count(name))
    throw std::invalid_argument("pass harness '" + name_ + "' already has a resource '" + name + "'");
}

vk::Image& PassHarness::add_image(const std::string& name, uint32_t width, uint32_t height, PixelFormat format,
                                  bool read_back) {
  check_new(name);
  auto& image = images_[name] = std::make_unique<vk::Image>(context_, vk::ImageDesc{name, width, height, format});
  if (read_back) image_outputs_.push_back(name);
  return *image;
}

vk::Image& PassHarness::input(const std::string& name, const HostImage& pixels) {
  vk::Image& image = add_image(name, pixels.width, pixels.height, pixels.format, false);
  vk::upload(context_, image, pixels);
  return image;
}

vk::Image& PassHarness::output(const std::string& name, uint32_t width, uint32_t height, PixelFormat format) {
  return add_image(name, width, height, format, true);
}

vk::Image& PassHarness::scratch(const std::string& name, uint32_t width, uint32_t height, PixelFormat format) {
  return add_image(name, width, height, format, false);
}

vk::Buffer& PassHarness::add_buffer(const vk::BufferDesc& desc, std::span<const std::byte> contents,
                                    size_t read_back_bytes) {
  check_new(desc.name);
  auto& buffer = buffers_[desc.name] = std::make_unique<vk::Buffer>(context_, desc);
  if (!contents.empty()) vk::upload(context_, *buffer, contents);
  if (read_back_bytes != kNoReadBack) buffer_outputs_.emplace_back(desc.name, read_back_bytes);
  return *buffer;
}

vk::Buffer& PassHarness::buffer(const vk::BufferDesc& desc, std::span<const std::byte> contents, bool read_back) {
  return add_buffer(desc, contents, read_back ? size_t(desc.size) : kNoReadBack);
}

PassOutputs PassHarness::run(uint32_t frames) {
  vk::FrameGraph& frame_graph = graph();
  ran_ = true;
  for (uint32_t frame = 0; frame < frames; ++frame) frame_graph.run();
  PassOutputs outputs;
  for (const std::string& name : image_outputs_) outputs.images_[name] = vk::download(context_, *images_.at(name));
  for (const auto& [name, bytes] : buffer_outputs_) {
    std::vector<std::byte> data = vk::download(context_, *buffers_.at(name));
    data.resize(bytes);
    outputs.buffers_[name] = std::move(data);
  }
  graph_.reset();  // its kernels need not outlive the harness, only this run
  return outputs;
}

}  // namespace rt::test
