#include "pipeline/depth_registration.h"

#include <span>
#include <stdexcept>
#include <string>

namespace rt::pipeline {

DepthRegistration::DepthRegistration(vk::Context& context, const CameraIntrinsics& depth, const CameraIntrinsics& color,
                                     const Eigen::Isometry3d& color_from_depth,
                                     const passes::DepthInColorSettings& settings,
                                     const std::optional<passes::DepthOutliersSettings>& outliers)
    : context_(context),
      pass_(context, settings),
      depth_(context, {.name = "depth mm", .width = depth.width, .height = depth.height, .format = PixelFormat::R16U}),
      filtered_(context, {.name = "depth mm without outliers", .width = outliers ? depth.width : 1u,
                          .height = outliers ? depth.height : 1u, .format = PixelFormat::R16U}),
      registered_(context,
                  {.name = "depth in color", .width = color.width, .height = color.height, .format = PixelFormat::R16U}),
      rays_(context, passes::depth_in_color_rays_desc(depth.width, depth.height)),
      nearest_(context, passes::depth_in_color_nearest_desc(color.width, color.height)),
      params_(passes::depth_in_color_params(color, color_from_depth)),
      graph_(context, "depth registration") {
  const std::vector<float> rays = passes::depth_in_color_rays(depth);
  vk::upload(context, rays_, std::as_bytes(std::span(rays)));
  if (outliers) {
    outliers_.emplace(context, *outliers);
    outliers_->add_to(graph_, depth_, filtered_);
  }
  pass_.add_to(graph_, outliers ? filtered_ : depth_, rays_, nearest_, registered_, [this] { return params_; });
}

HostImage DepthRegistration::run(const HostImage& depth_mm) {
  if (depth_mm.format != PixelFormat::R16U || depth_mm.width != depth_.width() || depth_mm.height != depth_.height())
    throw std::invalid_argument("depth registration: the depth image is " + std::to_string(depth_mm.width) + "x" +
                                std::to_string(depth_mm.height) + " " + format_name(depth_mm.format) + ", not the camera's " +
                                std::to_string(depth_.width()) + "x" + std::to_string(depth_.height()) + " r16u");
  vk::upload(context_, depth_, depth_mm);
  graph_.run();
  return vk::download(context_, registered_);
}

double DepthRegistration::median_ms() const {
  double total = 0;
  for (const vk::PassTiming& timing : graph_.timings()) total += timing.median_ms;
  return total;
}

}  // namespace rt::pipeline
