#include "pipeline/recorded_depth_registration.h"

#include <stdexcept>
#include <string>

namespace rt::pipeline {

namespace {

bool aligned(const sim::RecordedRgbdSource::RecordedIntrinsics& camera) {
  return (camera.color_from_depth.matrix() - Eigen::Matrix4d::Identity()).cwiseAbs().maxCoeff() < 1e-9;
}

}  // namespace

RecordedDepthRegistration::RecordedDepthRegistration(
    vk::Context& context, const std::vector<sim::RecordedRgbdSource::RecordedIntrinsics>& cameras) {
  for (const auto& camera : cameras)
    registrations_.push_back(aligned(camera) ? nullptr
                                             : std::make_unique<DepthRegistration>(context, camera.depth, camera.color,
                                                                                   camera.color_from_depth,
                                                                                   passes::DepthInColorSettings{},
                                                                                   passes::DepthOutliersSettings{}));
}

size_t RecordedDepthRegistration::registered_count() const {
  size_t count = 0;
  for (const auto& registration : registrations_) count += registration != nullptr;
  return count;
}

std::vector<passes::IbrCameraModel> RecordedDepthRegistration::models(std::vector<passes::IbrCameraModel> recorded) const {
  if (recorded.size() != registrations_.size())
    throw std::invalid_argument("depth registration: " + std::to_string(recorded.size()) + " camera models for " +
                                std::to_string(registrations_.size()) + " recorded cameras");
  for (size_t k = 0; k < recorded.size(); ++k)
    if (registrations_[k]) recorded[k].depth = recorded[k].color;
  return recorded;
}

void RecordedDepthRegistration::apply(std::vector<sim::RgbdImage>& cameras) {
  if (cameras.size() != registrations_.size())
    throw std::invalid_argument("depth registration: a frame of " + std::to_string(cameras.size()) + " cameras for " +
                                std::to_string(registrations_.size()) + " recorded cameras");
  for (size_t k = 0; k < cameras.size(); ++k)
    if (registrations_[k]) cameras[k].depth_mm = registrations_[k]->run(cameras[k].depth_mm);
}

double RecordedDepthRegistration::median_ms() const {
  double total = 0;
  size_t count = 0;
  for (const auto& registration : registrations_)
    if (registration) total += registration->median_ms(), ++count;
  return count ? total / double(count) : 0.0;
}

}  // namespace rt::pipeline
