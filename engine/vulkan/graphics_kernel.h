#pragma once
// A graphics pipeline (vertex + fragment) for dynamic rendering, built from SPIR-V alone like
// ComputeKernel, every specialization constant of either stage set by name. Vertices are pulled
// from storage buffers by gl_VertexIndex, so there is no vertex-input state to keep in step with
// the shader. Triangle lists, no culling (meshes are drawn from both sides of the glass), depth
// test LESS with writes when a depth format is set.
#include <vulkan/vulkan.h>

#include <span>
#include <string>
#include <vector>

#include "image/host_image.h"
#include "vulkan/pipeline_parts.h"

namespace rt::vk {

struct GraphicsTargets {
  std::vector<PixelFormat> color;           // one per fragment output, in location order
  bool depth = true;                        // a D32F depth attachment
};

class GraphicsKernel {
 public:
  GraphicsKernel(Context& context, std::string name, std::span<const uint32_t> vertex_spirv,
                 std::span<const uint32_t> fragment_spirv, const GraphicsTargets& targets,
                 const std::vector<Knob>& knobs = {});

  const std::string& name() const { return interface_.name; }
  const PipelineInterface& interface() const { return interface_; }
  const GraphicsTargets& targets() const { return targets_; }

 private:
  GraphicsTargets targets_;
  PipelineInterface interface_;
  PipelineLayoutParts layout_;
  Handle<VkPipeline> pipeline_;
};

}  // namespace rt::vk
