#pragma once
// Runs a pass (or a short chain of them) on host data, so that a pass test holds only its
// cases: named host images and buffers are uploaded, the pass records itself into the
// harness's frame graph, the graph runs, and the named outputs come back.
//
//   const passes::ColorSensorPass pass(test::gpu(), model);  // declared first: it outlives the graph
//   test::PassHarness gpu("color_sensor");
//   pass.add_to(gpu.graph(), gpu.input("rendered", rendered), gpu.output("sensed", w, h, PixelFormat::RGBA8));
//   const HostImage sensed = gpu.run().image("sensed");
//
// Resources take their names from the test, so a validation message or a pass's refusal names
// them as the test does.
#include <algorithm>
#include <cstddef>
#include <cstring>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "image/host_image.h"
#include "vulkan/frame_graph.h"
#include "vulkan/resources.h"

namespace rt::test {

// What a run read back, by the names given to PassHarness::output and its buffer outputs.
class PassOutputs {
 public:
  const HostImage& image(const std::string& name) const;
  const std::vector<std::byte>& bytes(const std::string& name) const;
  // The buffer's bytes as values of T (its size must be a whole number of them).
  template <typename T>
  std::vector<T> values(const std::string& name) const {
    const std::vector<std::byte>& data = bytes(name);
    check_whole(name, data.size(), sizeof(T));
    std::vector<T> out(data.size() / sizeof(T));
    if (!out.empty()) std::memcpy(out.data(), data.data(), out.size() * sizeof(T));
    return out;
  }
  // A buffer holding exactly one T.
  template <typename T>
  T value(const std::string& name) const {
    const std::vector<T> all = values<T>(name);
    check_single(name, all.size());
    return all.front();
  }

 private:
  friend class PassHarness;
  static void check_whole(const std::string& name, size_t bytes, size_t value_size);
  static void check_single(const std::string& name, size_t count);
  std::map<std::string, HostImage> images_;
  std::map<std::string, std::vector<std::byte>> buffers_;
};

class PassHarness {
 public:
  // The frame graph is named "test <name>"; the context is test::gpu().
  explicit PassHarness(const std::string& name);
  ~PassHarness();
  PassHarness(const PassHarness&) = delete;
  PassHarness& operator=(const PassHarness&) = delete;

  vk::Context& context() const { return context_; }
  // Passes record into this; kernels given to it must outlive run() (declare them first).
  vk::FrameGraph& graph();

  // An image holding `pixels` (their size and format).
  vk::Image& input(const std::string& name, const HostImage& pixels);
  // An image the pass writes; run() reads it back.
  vk::Image& output(const std::string& name, uint32_t width, uint32_t height, PixelFormat format);
  // An image neither uploaded nor read back (e.g. a depth attachment).
  vk::Image& scratch(const std::string& name, uint32_t width, uint32_t height, PixelFormat format);

  // A storage buffer holding `values` (a contiguous range, or std::span(&one, 1)). Room for at
  // least one value, so that an empty input is still a valid buffer. With `read_back` the pass
  // may also write it, and run() reads back as many values as it started with.
  template <typename Values>
  vk::Buffer& input_buffer(const std::string& name, const Values& values, bool read_back = false) {
    const auto view = std::span(values);
    const size_t one = sizeof(typename decltype(view)::element_type);
    return add_buffer({name, std::max(view.size_bytes(), one)}, std::as_bytes(view),
                      read_back ? view.size_bytes() : kNoReadBack);
  }
  // A storage buffer the pass writes: run() reads back `count` values of T (room for one at least).
  template <typename T>
  vk::Buffer& output_buffer(const std::string& name, size_t count) {
    return add_buffer({name, std::max<size_t>(count, 1) * sizeof(T)}, {}, count * sizeof(T));
  }
  // A buffer of the pass's own description (its size and usage), optionally filled with
  // `contents`; `read_back` reads all of it back under desc.name.
  vk::Buffer& buffer(const vk::BufferDesc& desc, std::span<const std::byte> contents = {}, bool read_back = false);

  // Runs the graph `frames` times, then reads back every output. Once per harness.
  PassOutputs run(uint32_t frames = 1);

 private:
  static constexpr size_t kNoReadBack = ~size_t(0);
  vk::Image& add_image(const std::string& name, uint32_t width, uint32_t height, PixelFormat format, bool read_back);
  vk::Buffer& add_buffer(const vk::BufferDesc& desc, std::span<const std::byte> contents, size_t read_back_bytes);
  void check_new(const std::string& name) const;

  vk::Context& context_;
  std::string name_;
  std::map<std::string, std::unique_ptr<vk::Image>> images_;
  std::map<std::string, std::unique_ptr<vk::Buffer>> buffers_;
  std::vector<std::string> image_outputs_;
  std::vector<std::pair<std::string, size_t>> buffer_outputs_;  // name, bytes to read back
  std::unique_ptr<vk::FrameGraph> graph_;
  bool ran_ = false;
};

}  // namespace rt::test
