#pragma once
// The frame graph: passes declare what they read and write and record themselves; the graph
// orders them, inserts every barrier (the only place in the engine that decides
// synchronization), wraps each pass in a debug label named after it, and brackets it with
// timestamp queries so that per-pass GPU times cost a pass nothing. Resources carry their
// names from creation (the graph refuses unnamed ones); kernels and resources given to the
// graph must outlive it.
#include <vulkan/vulkan.h>

#include <array>
#include <cstddef>
#include <functional>
#include <memory>
#include <string>
#include <variant>
#include <vector>

#include "vulkan/compute_kernel.h"
#include "vulkan/graphics_kernel.h"
#include "vulkan/resources.h"

namespace rt::vk {

using ResourceRef = std::variant<Image*, Buffer*>;

std::string resource_name(const ResourceRef& resource);

struct ResourceUse {
  ResourceRef resource;
  Access access;
};

// A pass with any commands (copies, clears, draws): the graph trusts `uses` for its barriers.
struct PassDecl {
  std::string name;
  std::vector<ResourceUse> uses;
  std::function<void(VkCommandBuffer)> record;
};

// A resource bound to a shader binding, by the binding's name in the shader.
struct Binding {
  std::string name{};
  ResourceRef resource{};
  const Sampler* sampler = nullptr;  // for sampled images only
};

// A compute pass: its reads and writes follow from the shader's own qualifiers (readonly,
// writeonly), its descriptor layout and workgroup size from the kernel's reflection.
struct ComputePassDecl {
  std::string name{};
  const ComputeKernel* kernel = nullptr;
  std::vector<Binding> bindings{};
  std::array<uint32_t, 3> threads{1, 1, 1};  // invocations per axis, e.g. {width, height, 1}
  // Called when each frame is recorded; its size must equal the shader's push-constant block.
  std::function<std::vector<std::byte>()> push_constants{};
  // When set, the workgroup counts are the buffer's first three uints as an earlier pass wrote
  // them (vkCmdDispatchIndirect; the buffer needs VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT), and
  // `threads` is not used.
  Buffer* indirect = nullptr;
};

struct ColorTarget {
  Image* image = nullptr;
  std::array<float, 4> clear{0, 0, 0, 0};  // every draw pass clears its targets first
};

// A draw: the kernel's vertex shader pulls vertex_count() vertices from its storage buffers.
// Color targets in the order of the fragment shader's outputs; depth is D32F, cleared to 1.
struct GraphicsPassDecl {
  std::string name{};
  const GraphicsKernel* kernel = nullptr;
  std::vector<Binding> bindings{};
  std::vector<ColorTarget> color{};
  Image* depth = nullptr;
  std::function<uint32_t()> vertex_count{};  // read when each frame is recorded
  std::function<std::vector<std::byte>()> push_constants{};
};

// Push constants from a value of the struct shared with the shader (shaders/shared/config.h).
template <typename T>
std::function<std::vector<std::byte>()> push_constants_from(std::function<T()> value) {
  return [value = std::move(value)] {
    const T data = value();
    const auto* bytes = reinterpret_cast<const std::byte*>(&data);
    return std::vector<std::byte>(bytes, bytes + sizeof(T));
  };
}

struct PassTiming {
  std::string name;
  double median_ms = 0.0;  // over every frame run so far (at most the last kMaxTimedFrames)
  double last_ms = 0.0;
  size_t frames = 0;
  uint64_t bytes_moved = 0;  // bytes of the resources it reads plus those it writes
  // The bandwidth the median time achieves; 0 before any frame.
  double gigabytes_per_second() const { return median_ms > 0 ? double(bytes_moved) / (median_ms * 1e-3) / 1e9 : 0.0; }
};

class FrameGraph {
 public:
  static constexpr size_t kMaxTimedFrames = 1024;

  FrameGraph(Context& context, std::string name);
  ~FrameGraph();
  FrameGraph(const FrameGraph&) = delete;
  FrameGraph& operator=(const FrameGraph&) = delete;

  void add_pass(PassDecl pass);
  // A copy of one image into another of the same size and format, on the device.
  void add_image_copy(const std::string& name, Image& source, Image& destination);
  void add_compute_pass(ComputePassDecl pass);    // checks bindings, formats and sizes against the shader
  void add_graphics_pass(GraphicsPassDecl pass);  // the same checks, and the targets' formats and sizes

  // Pass names in execution order: every pass runs after the passes that write what it reads;
  // otherwise in the order added. Throws when the passes form a cycle.
  std::vector<std::string> execution_order();

  // Records all passes, submits and waits for the GPU; then reads the timestamps.
  void run();

  std::vector<PassTiming> timings() const;  // in execution order
  void reset_timings();                     // e.g. after warm-up frames
  // Barriers the last frame recorded before each pass, in execution order.
  std::vector<size_t> barriers_per_pass() const;
  // The images each pass writes, as (pass name, image), in execution order: for dumping outputs.
  std::vector<std::pair<std::string, Image*>> written_images() const;
  size_t frames_run() const { return frames_run_; }
  bool timing_available() const { return timestamp_period_ns_ > 0.0; }

 private:
  struct Pass;
  void compile();

  Context& context_;
  std::string name_;
  std::vector<std::unique_ptr<Pass>> passes_;
  std::vector<size_t> order_;
  bool compiled_ = false;
  CommandBuffer commands_;
  Handle<VkQueryPool> queries_;
  double timestamp_period_ns_ = 0.0;
  uint64_t timestamp_mask_ = 0;
  bool cpu_timestamps_ = false;  // llvmpipe: a pass's time is the gap between end stamps (run())
  size_t frames_run_ = 0;
};

// A table of per-pass GPU times and achieved bandwidth, for --profile and the benchmarks.
std::string format_profile(const std::vector<PassTiming>& timings);

}  // namespace rt::vk
