#include "vulkan/frame_graph.h"

#include <algorithm>
#include <cstdio>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>

#include "vulkan/check.h"
#include "vulkan/vk_struct.h"

namespace rt::vk {

struct FrameGraph::Pass {
  PassDecl decl;
  uint64_t bytes_moved = 0;
  std::vector<double> gpu_ms;
  size_t barriers = 0;
};

namespace {

const void* identity(const ResourceRef& resource) {
  return std::visit([](auto* r) -> const void* { return r; }, resource);
}

size_t size_of(const ResourceRef& resource) {
  if (auto* image = std::get_if<Image*>(&resource)) return (*image)->size_bytes();
  return size_t(std::get<Buffer*>(resource)->size());
}

double median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  const size_t middle = values.size() / 2;
  std::nth_element(values.begin(), values.begin() + middle, values.end());
  if (values.size() % 2 == 1) return values[middle];
  const double upper = values[middle];
  return (upper + *std::max_element(values.begin(), values.begin() + middle)) / 2.0;
}

Access compute_access(const ShaderBinding& binding) {
  if (binding.type == VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER) return access::compute_sample;
  if (binding.readable && binding.writable) return access::compute_read_write;
  return binding.writable ? access::compute_write : access::compute_read;
}

}  // namespace

std::string resource_name(const ResourceRef& resource) {
  return std::visit([](auto* r) { return r->name(); }, resource);
}

FrameGraph::FrameGraph(Context& context, std::string name)
    : context_(context), name_(std::move(name)), commands_(context, name_ + " commands") {}

FrameGraph::~FrameGraph() = default;

void FrameGraph::add_pass(PassDecl decl) {
  for (const auto& pass : passes_)
    if (pass->decl.name == decl.name) throw std::invalid_argument("frame graph '" + name_ + "' already has a pass '" + decl.name + "'");
  if (!decl.record) throw std::invalid_argument("pass '" + decl.name + "' has nothing to record");
  auto pass = std::make_unique<Pass>();
  for (const ResourceUse& use : decl.uses) {
    if (!identity(use.resource)) throw std::invalid_argument("pass '" + decl.name + "' uses a null resource");
    if (resource_name(use.resource).empty())
      throw std::invalid_argument("pass '" + decl.name + "' uses an unnamed resource; name it (captures and validation "
                                  "messages show the name)");
    if (writes(use.access.access)) pass->bytes_moved += size_of(use.resource);
    if (reads(use.access.access)) pass->bytes_moved += size_of(use.resource);
  }
  pass->decl = std::move(decl);
  passes_.push_back(std::move(pass));
  compiled_ = false;
}

namespace {

Access binding_access(const ShaderBinding& binding, VkPipelineBindPoint bind_point) {
  if (bind_point == VK_PIPELINE_BIND_POINT_COMPUTE) return compute_access(binding);
  Access access = access::graphics_read;
  if (binding.type == VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER) {
    access.access = VK_ACCESS_2_SHADER_SAMPLED_READ_BIT;
    access.layout = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
  } else if (binding.writable) {
    access.access = (binding.readable ? VK_ACCESS_2_SHADER_STORAGE_READ_BIT : VK_ACCESS_2_NONE) |
                    VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT;
  }
  return access;
}

using BoundList = std::vector<std::pair<ShaderBinding, Binding>>;

// Checks `given` against the pipeline's bindings (every one bound once, by name, with a
// resource of the right kind and format) and returns them with the uses they imply.
BoundList resolve_bindings(const std::string& pass, const PipelineInterface& pipeline,
                           const std::vector<Binding>& given, std::vector<ResourceUse>& uses) {
  auto fail = [&](const std::string& what) { return std::invalid_argument("pass '" + pass + "': " + what); };
  BoundList bound;
  for (const Binding& binding : given) {
    const ShaderBinding* declared = pipeline.find_binding(binding.name);
    if (!declared) {
      std::string known;
      for (const auto& b : pipeline.bindings) known += (known.empty() ? "" : ", ") + b.name;
      throw fail("shader '" + pipeline.name + "' has no binding '" + binding.name + "' (it has: " + known + ")");
    }
    for (const auto& [other, unused] : bound)
      if (other.binding == declared->binding) throw fail("binding '" + binding.name + "' is bound twice");
    if (!identity(binding.resource)) throw fail("binding '" + binding.name + "' is given a null resource");
    const bool is_image = std::holds_alternative<Image*>(binding.resource);
    const bool wants_image = declared->type == VK_DESCRIPTOR_TYPE_STORAGE_IMAGE ||
                             declared->type == VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
    if (is_image != wants_image)
      throw fail("binding '" + binding.name + "' is " + (wants_image ? "an image" : "a buffer") +
                 " in the shader, given " + (is_image ? "image" : "buffer") + " '" + resource_name(binding.resource) + "'");
    if (declared->type == VK_DESCRIPTOR_TYPE_STORAGE_IMAGE && declared->image_format != VK_FORMAT_UNDEFINED) {
      const Image& image = *std::get<Image*>(binding.resource);
      if (image.format() != declared->image_format)
        throw fail("binding '" + binding.name + "' is declared with format " + std::to_string(declared->image_format) +
                   " in the shader, given image '" + image.name() + "' of format " + format_name(image.pixel_format()) +
                   " (" + std::to_string(image.format()) + ")");
    }
    if (declared->type == VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER && !binding.sampler)
      throw fail("binding '" + binding.name + "' is a sampled image and needs a sampler");
    bound.emplace_back(*declared, binding);
    uses.push_back({binding.resource, binding_access(*declared, pipeline.bind_point)});
  }
  for (const auto& declared : pipeline.bindings) {
    bool found = false;
    for (const auto& [other, unused] : bound) found |= other.binding == declared.binding;
    if (!found) throw fail("shader binding '" + declared.name + "' is not bound");
  }
  return bound;
}

using PushFunction = std::function<std::vector<std::byte>()>;

void check_push_given(const std::string& pass, const PipelineInterface& pipeline, const PushFunction& push) {
  if (pipeline.push_constant_size > 0 && !push)
    throw std::invalid_argument("pass '" + pass + "': shader '" + pipeline.name + "' takes " +
                                std::to_string(pipeline.push_constant_size) + " bytes of push constants and none are given");
}

// Binds the pipeline, its resources (push descriptors) and its push constants.
void bind_pipeline(const Context& context, VkCommandBuffer commands, const std::string& pass,
                   const PipelineInterface& pipeline, const BoundList& bound, const PushFunction& push) {
  vkCmdBindPipeline(commands, pipeline.bind_point, pipeline.pipeline);
  std::vector<VkDescriptorImageInfo> image_infos;
  std::vector<VkDescriptorBufferInfo> buffer_infos;
  image_infos.reserve(bound.size());
  buffer_infos.reserve(bound.size());
  std::vector<VkWriteDescriptorSet> writes;
  for (const auto& [declared, binding] : bound) {
    auto write = vk_struct<VkWriteDescriptorSet>(VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET);
    write.dstBinding = declared.binding;
    write.descriptorCount = 1;
    write.descriptorType = declared.type;
    if (auto* image = std::get_if<Image*>(&binding.resource)) {
      image_infos.push_back({binding.sampler ? binding.sampler->get() : VK_NULL_HANDLE, (*image)->view(),
                             binding_access(declared, pipeline.bind_point).layout});
      write.pImageInfo = &image_infos.back();
    } else {
      buffer_infos.push_back({std::get<Buffer*>(binding.resource)->buffer(), 0, VK_WHOLE_SIZE});
      write.pBufferInfo = &buffer_infos.back();
    }
    writes.push_back(write);
  }
  if (!writes.empty())
    context.push_descriptor_set(commands, pipeline.bind_point, pipeline.layout, 0, uint32_t(writes.size()), writes.data());
  if (const uint32_t size = pipeline.push_constant_size; size > 0) {
    const std::vector<std::byte> data = push();
    if (data.size() != size)
      throw std::logic_error("pass '" + pass + "' pushed " + std::to_string(data.size()) + " bytes; shader '" +
                             pipeline.name + "' declares " + std::to_string(size));
    vkCmdPushConstants(commands, pipeline.layout, pipeline.push_constant_stages, 0, size, data.data());
  }
}

}  // namespace

void FrameGraph::add_image_copy(const std::string& name, Image& source, Image& destination) {
  if (source.width() != destination.width() || source.height() != destination.height() ||
      source.pixel_format() != destination.pixel_format())
    throw std::invalid_argument("pass '" + name + "': '" + source.name() + "' and '" + destination.name() +
                                "' differ in size or format");
  add_pass({name,
            {{&source, access::transfer_read}, {&destination, access::transfer_write}},
            [&source, &destination](VkCommandBuffer commands) {
              VkImageCopy region{};
              region.srcSubresource = region.dstSubresource = {aspect_of(source.pixel_format()), 0, 0, 1};
              region.extent = {source.width(), source.height(), 1};
              vkCmdCopyImage(commands, source.image(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, destination.image(),
                             VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
            }});
}

void FrameGraph::add_compute_pass(ComputePassDecl decl) {
  auto fail = [&](const std::string& what) { return std::invalid_argument("pass '" + decl.name + "': " + what); };
  if (!decl.kernel) throw fail("no kernel");
  const ComputeKernel& kernel = *decl.kernel;
  std::vector<ResourceUse> uses;
  BoundList bound = resolve_bindings(decl.name, kernel.interface(), decl.bindings, uses);
  check_push_given(decl.name, kernel.interface(), decl.push_constants);
  if (decl.indirect) {
    if (decl.indirect->size() < 3 * sizeof(uint32_t)) throw fail("the indirect buffer holds fewer than three uints");
    uses.push_back({decl.indirect, access::indirect_read});
  }
  const auto groups = kernel.group_count(decl.threads);
  const auto& limits = context_.properties().limits;
  for (int axis = 0; decl.indirect == nullptr && axis < 3; ++axis) {
    if (decl.threads[axis] == 0) throw fail("a thread count of 0 on axis " + std::to_string(axis));
    if (groups[axis] > limits.maxComputeWorkGroupCount[axis])
      throw fail(std::to_string(groups[axis]) + " workgroups on axis " + std::to_string(axis) + " exceed the device's " +
                 std::to_string(limits.maxComputeWorkGroupCount[axis]));
  }
  const Context& context = context_;
  auto record = [&context, &kernel, bound = std::move(bound), groups, name = decl.name,
                 push = std::move(decl.push_constants), indirect = decl.indirect](VkCommandBuffer commands) {
    bind_pipeline(context, commands, name, kernel.interface(), bound, push);
    if (indirect)
      vkCmdDispatchIndirect(commands, indirect->buffer(), 0);
    else
      vkCmdDispatch(commands, groups[0], groups[1], groups[2]);
  };
  add_pass({decl.name, std::move(uses), std::move(record)});
}

void FrameGraph::add_graphics_pass(GraphicsPassDecl decl) {
  auto fail = [&](const std::string& what) { return std::invalid_argument("pass '" + decl.name + "': " + what); };
  if (!decl.kernel) throw fail("no kernel");
  const GraphicsKernel& kernel = *decl.kernel;
  if (!decl.vertex_count) throw fail("no vertex count");
  std::vector<ResourceUse> uses;
  BoundList bound = resolve_bindings(decl.name, kernel.interface(), decl.bindings, uses);
  check_push_given(decl.name, kernel.interface(), decl.push_constants);

  const GraphicsTargets& targets = kernel.targets();
  if (decl.color.size() != targets.color.size())
    throw fail("kernel '" + kernel.name() + "' draws " + std::to_string(targets.color.size()) + " color targets, given " +
               std::to_string(decl.color.size()));
  if (targets.depth != (decl.depth != nullptr))
    throw fail(targets.depth ? "the kernel needs a depth target" : "the kernel has no depth target");
  const Image* first = decl.color.empty() ? decl.depth : decl.color.front().image;
  if (!first) throw fail("nothing to draw into");
  const VkExtent2D extent{first->width(), first->height()};
  for (size_t i = 0; i < decl.color.size(); ++i) {
    const Image* image = decl.color[i].image;
    if (!image) throw fail("color target " + std::to_string(i) + " is null");
    if (image->pixel_format() != targets.color[i])
      throw fail("color target " + std::to_string(i) + " '" + image->name() + "' is " + format_name(image->pixel_format()) +
                 ", the kernel draws " + format_name(targets.color[i]));
    uses.push_back({decl.color[i].image, access::color_attachment_write});
  }
  if (decl.depth) {
    if (decl.depth->pixel_format() != PixelFormat::D32F) throw fail("depth target '" + decl.depth->name() + "' is not d32f");
    uses.push_back({decl.depth, access::depth_attachment_write});
  }
  // Only attachments share the render area; a sampled texture has its own size.
  for (const ResourceUse& use : uses)
    if (auto* image = std::get_if<Image*>(&use.resource);
        image &&
        (use.access.layout == VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL ||
         use.access.layout == VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL) &&
        ((*image)->width() != extent.width || (*image)->height() != extent.height))
      throw fail("target '" + (*image)->name() + "' differs in size from the others");

  const Context& context = context_;
  auto record = [&context, &kernel, bound = std::move(bound), name = decl.name, push = std::move(decl.push_constants),
                 color = decl.color, depth = decl.depth, extent, count = std::move(decl.vertex_count)](VkCommandBuffer commands) {
    std::vector<VkRenderingAttachmentInfo> color_infos;
    for (const ColorTarget& target : color) {
      auto info = vk_struct<VkRenderingAttachmentInfo>(VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO);
      info.imageView = target.image->view();
      info.imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
      info.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
      info.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
      // Integer targets (r16ui) clear through the same bits as floats would not: set both views.
      for (int c = 0; c < 4; ++c) {
        info.clearValue.color.float32[c] = target.clear[c];
      }
      if (target.image->pixel_format() == PixelFormat::R16U)
        for (int c = 0; c < 4; ++c) info.clearValue.color.uint32[c] = uint32_t(target.clear[c]);
      color_infos.push_back(info);
    }
    auto depth_info = vk_struct<VkRenderingAttachmentInfo>(VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO);
    if (depth) {
      depth_info.imageView = depth->view();
      depth_info.imageLayout = VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL;
      depth_info.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
      depth_info.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
      depth_info.clearValue.depthStencil = {1.0f, 0};
    }
    auto rendering = vk_struct<VkRenderingInfo>(VK_STRUCTURE_TYPE_RENDERING_INFO);
    rendering.renderArea = {{0, 0}, extent};
    rendering.layerCount = 1;
    rendering.colorAttachmentCount = uint32_t(color_infos.size());
    rendering.pColorAttachments = color_infos.data();
    rendering.pDepthAttachment = depth ? &depth_info : nullptr;
    context.begin_rendering(commands, rendering);
    const VkViewport viewport{0, 0, float(extent.width), float(extent.height), 0, 1};
    const VkRect2D scissor{{0, 0}, extent};
    vkCmdSetViewport(commands, 0, 1, &viewport);
    vkCmdSetScissor(commands, 0, 1, &scissor);
    bind_pipeline(context, commands, name, kernel.interface(), bound, push);
    if (const uint32_t vertices = count(); vertices > 0) vkCmdDraw(commands, vertices, 1, 0, 0);
    context.end_rendering(commands);
  };
  add_pass({decl.name, std::move(uses), std::move(record)});
}

void FrameGraph::compile() {
  if (compiled_) return;
  const size_t count = passes_.size();
  // A pass that reads a resource runs after every pass that writes it; passes that both write
  // one resource (a clear, then an accumulation) keep the order in which they were added.
  // Within a frame a resource is therefore produced, then consumed, never produced again.
  std::vector<std::set<size_t>> after(count);  // after[j]: passes that must run before j
  for (size_t j = 0; j < count; ++j)
    for (const ResourceUse& use : passes_[j]->decl.uses)
      for (size_t i = 0; i < count; ++i) {
        if (i == j) continue;
        for (const ResourceUse& other : passes_[i]->decl.uses) {
          if (identity(other.resource) != identity(use.resource) || !writes(other.access.access)) continue;
          if (!writes(use.access.access) || i < j) after[j].insert(i);
        }
      }

  // Kahn's algorithm, taking the earliest-added ready pass each time.
  order_.clear();
  std::vector<bool> done(count, false);
  for (size_t step = 0; step < count; ++step) {
    size_t chosen = count;
    for (size_t j = 0; j < count && chosen == count; ++j) {
      if (done[j]) continue;
      bool ready = true;
      for (size_t i : after[j]) ready &= done[i];
      if (ready) chosen = j;
    }
    if (chosen == count) {
      std::string stuck;
      for (size_t j = 0; j < count; ++j)
        if (!done[j]) stuck += (stuck.empty() ? "" : ", ") + passes_[j]->decl.name;
      throw std::invalid_argument("frame graph '" + name_ + "': passes " + stuck +
                                  " read each other's outputs in a cycle; split a resource or reorder");
    }
    done[chosen] = true;
    order_.push_back(chosen);
  }

  // Two timestamps per pass. Without timestamp support the graph still runs, untimed.
  queries_ = Handle<VkQueryPool>();
  timestamp_period_ns_ = 0.0;
  const uint32_t valid_bits = [&] {
    uint32_t family_count = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(context_.physical_device(), &family_count, nullptr);
    std::vector<VkQueueFamilyProperties> families(family_count);
    vkGetPhysicalDeviceQueueFamilyProperties(context_.physical_device(), &family_count, families.data());
    return families[context_.queue_family()].timestampValidBits;
  }();
  if (count > 0 && valid_bits > 0) {
    auto info = vk_struct<VkQueryPoolCreateInfo>(VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO);
    info.queryType = VK_QUERY_TYPE_TIMESTAMP;
    info.queryCount = uint32_t(2 * count + 1);  // + one at the start of the frame
    VkQueryPool pool = VK_NULL_HANDLE;
    RT_VK_CHECK(vkCreateQueryPool(context_.device(), &info, nullptr, &pool));
    queries_ = Handle<VkQueryPool>(context_, pool);
    context_.set_name(VK_OBJECT_TYPE_QUERY_POOL, uint64_t(pool), name_ + " pass timestamps");
    timestamp_period_ns_ = context_.properties().limits.timestampPeriod;
    timestamp_mask_ = valid_bits >= 64 ? ~0ull : ((1ull << valid_bits) - 1);
    auto driver = vk_struct<VkPhysicalDeviceDriverProperties>(VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES);
    auto properties = vk_struct<VkPhysicalDeviceProperties2>(VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2, &driver);
    vkGetPhysicalDeviceProperties2(context_.physical_device(), &properties);
    cpu_timestamps_ = driver.driverID == VK_DRIVER_ID_MESA_LLVMPIPE;
  }
  compiled_ = true;
}

std::vector<std::string> FrameGraph::execution_order() {
  compile();
  std::vector<std::string> names;
  for (size_t index : order_) names.push_back(passes_[index]->decl.name);
  return names;
}

void FrameGraph::run() {
  compile();
  VkCommandBuffer commands = commands_.get();
  // Recording touches the command pool, which other threads' graphs and uploads share.
  std::unique_lock pool = context_.lock_command_pool();
  auto begin = vk_struct<VkCommandBufferBeginInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO);
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  RT_VK_CHECK(vkBeginCommandBuffer(commands, &begin));
  if (queries_) {
    vkCmdResetQueryPool(commands, queries_.get(), 0, uint32_t(2 * passes_.size() + 1));
    context_.write_timestamp(commands, queries_.get(), uint32_t(2 * passes_.size()));
  }
  context_.begin_label(commands, name_);
  for (size_t slot = 0; slot < order_.size(); ++slot) {
    Pass& pass = *passes_[order_[slot]];
    context_.begin_label(commands, pass.decl.name);
    std::vector<VkImageMemoryBarrier2> image_barriers;
    std::vector<VkBufferMemoryBarrier2> buffer_barriers;
    for (const ResourceUse& use : pass.decl.uses) {
      if (auto* image = std::get_if<Image*>(&use.resource)) {
        if (auto plan = plan_access((*image)->state(), use.access, true)) image_barriers.push_back(image_barrier(**image, *plan));
      } else {
        Buffer& buffer = *std::get<Buffer*>(use.resource);
        if (auto plan = plan_access(buffer.state(), use.access, false)) buffer_barriers.push_back(buffer_barrier(buffer, *plan));
      }
    }
    pass.barriers = image_barriers.size() + buffer_barriers.size();
    if (pass.barriers > 0) {
      auto dependency = vk_struct<VkDependencyInfo>(VK_STRUCTURE_TYPE_DEPENDENCY_INFO);
      dependency.imageMemoryBarrierCount = uint32_t(image_barriers.size());
      dependency.pImageMemoryBarriers = image_barriers.data();
      dependency.bufferMemoryBarrierCount = uint32_t(buffer_barriers.size());
      dependency.pBufferMemoryBarriers = buffer_barriers.data();
      context_.pipeline_barrier(commands, dependency);
    }
    if (queries_) context_.write_timestamp(commands, queries_.get(), uint32_t(2 * slot));
    pass.decl.record(commands);
    if (queries_) context_.write_timestamp(commands, queries_.get(), uint32_t(2 * slot + 1));
    context_.end_label(commands);
  }
  context_.end_label(commands);
  RT_VK_CHECK(vkEndCommandBuffer(commands));
  const uint64_t done = context_.submit(commands);
  pool.unlock();
  context_.wait(done);
  ++frames_run_;

  if (!queries_) return;
  std::vector<uint64_t> stamps(2 * passes_.size() + 1);
  RT_VK_CHECK(vkGetQueryPoolResults(context_.device(), queries_.get(), 0, uint32_t(stamps.size()),
                                    stamps.size() * sizeof(uint64_t), stamps.data(), sizeof(uint64_t),
                                    VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT));
  const uint64_t frame_start = stamps[2 * passes_.size()];
  for (size_t slot = 0; slot < order_.size(); ++slot) {
    Pass& pass = *passes_[order_[slot]];
    uint64_t start = stamps[2 * slot] & timestamp_mask_;
    uint64_t end = stamps[2 * slot + 1] & timestamp_mask_;
    if (cpu_timestamps_) {
      // llvmpipe takes a timestamp either when the command runs or, once the context has drawn
      // anything, when its rasterizer runs the binned query at the next flush (every timestamp
      // command flushes first; compute work and transfers run synchronously, draws are binned).
      // Either way the stretch from one pass's end stamp to the next one's holds that pass's
      // work, plus a flush: so a pass's time on llvmpipe is the gap between consecutive end
      // stamps, the first measured from a stamp at the start of the frame.
      start = (slot == 0 ? frame_start : stamps[2 * slot - 1]) & timestamp_mask_;
    }
    const uint64_t ticks = (end - start) & timestamp_mask_;  // survives a counter wrap
    if (pass.gpu_ms.size() == kMaxTimedFrames) pass.gpu_ms.erase(pass.gpu_ms.begin());
    pass.gpu_ms.push_back(double(ticks) * timestamp_period_ns_ * 1e-6);
  }
}

std::vector<PassTiming> FrameGraph::timings() const {
  std::vector<PassTiming> result;
  for (size_t index : order_) {
    const Pass& pass = *passes_[index];
    PassTiming timing;
    timing.name = pass.decl.name;
    timing.frames = pass.gpu_ms.size();
    timing.median_ms = median(pass.gpu_ms);
    timing.last_ms = pass.gpu_ms.empty() ? 0.0 : pass.gpu_ms.back();
    timing.bytes_moved = pass.bytes_moved;
    result.push_back(timing);
  }
  return result;
}

void FrameGraph::reset_timings() {
  for (auto& pass : passes_) pass->gpu_ms.clear();
}

std::vector<size_t> FrameGraph::barriers_per_pass() const {
  std::vector<size_t> result;
  for (size_t index : order_) result.push_back(passes_[index]->barriers);
  return result;
}

std::vector<std::pair<std::string, Image*>> FrameGraph::written_images() const {
  std::vector<std::pair<std::string, Image*>> result;
  for (size_t index : order_)
    for (const ResourceUse& use : passes_[index]->decl.uses)
      if (auto* image = std::get_if<Image*>(&use.resource); image && writes(use.access.access))
        result.emplace_back(passes_[index]->decl.name, *image);
  return result;
}

std::string format_profile(const std::vector<PassTiming>& timings) {
  std::ostringstream out;
  char line[160];
  std::snprintf(line, sizeof line, "%-22s %10s %10s %8s %12s %10s\n", "pass", "median ms", "last ms", "frames", "MB moved",
                "GB/s");
  out << line;
  double total = 0.0;
  for (const PassTiming& timing : timings) {
    const double gb_per_s = timing.gigabytes_per_second();
    std::snprintf(line, sizeof line, "%-22s %10.3f %10.3f %8zu %12.2f %10.2f\n", timing.name.c_str(), timing.median_ms,
                  timing.last_ms, timing.frames, double(timing.bytes_moved) / 1e6, gb_per_s);
    out << line;
    total += timing.median_ms;
  }
  std::snprintf(line, sizeof line, "%-22s %10.3f\n", "sum of medians", total);
  out << line;
  return out.str();
}

}  // namespace rt::vk
