#include "passes/copy.h"

#include <stdexcept>

#include "copy.comp.h"

namespace rt::passes {

CopyPass::CopyPass(vk::Context& context) : kernel_(context, "copy", copy_comp_spirv) {}

void CopyPass::add_to(vk::FrameGraph& graph, vk::Image& source, vk::Image& destination,
                      const std::string& pass_name) const {
  if (source.width() != destination.width() || source.height() != destination.height())
    throw std::invalid_argument(pass_name + ": source and destination differ in size");
  graph.add_compute_pass({
      .name = pass_name,
      .kernel = &kernel_,
      .bindings = {{"source", &source}, {"destination", &destination}},
      .threads = {destination.width(), destination.height(), 1},
  });
}

}  // namespace rt::passes
