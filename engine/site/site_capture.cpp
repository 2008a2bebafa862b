#include "site/site_capture.h"

#include <iostream>

namespace rt::site {

namespace {
size_t index(SiteCapture::Stage stage) { return stage == SiteCapture::Stage::Sender ? 0 : 1; }
const char* stage_name(SiteCapture::Stage stage) { return stage == SiteCapture::Stage::Sender ? "sender" : "receiver"; }
}  // namespace

SiteCapture::SiteCapture(pipeline::GpuSession& gpu, int frame, std::string site_name)
    : gpu_(gpu), frame_(frame), site_name_(std::move(site_name)) {}

std::string SiteCapture::title(Stage stage) const {
  return stage == Stage::Sender
             ? "site " + site_name_ + " sender: the image-based model, portrait " + std::to_string(frame_)
             : "site " + site_name_ + " receiver: the geometry hand and the compositing, shown portrait " +
                   std::to_string(frame_);
}

SiteCapture::Scope SiteCapture::scope(Stage stage, uint64_t iteration) {
  if (frame_ < 0 || iteration != uint64_t(frame_) || !gpu_.capture_available()) return Scope(nullptr, stage);
  mutex_.lock();  // released by the scope's end
  if (paths_[index(stage)]) {
    mutex_.unlock();
    return Scope(nullptr, stage);
  }
  gpu_.begin_capture(title(stage));
  return Scope(this, stage);
}

SiteCapture::Scope::~Scope() {
  if (!owner_) return;
  try {
    owner_->paths_[index(stage_)] = owner_->gpu_.end_capture().value_or("(capture path unknown)");
  } catch (const std::exception& error) {
    std::cerr << "site " << owner_->site_name_ << ": RenderDoc capture of the " << stage_name(stage_)
              << " failed: " << error.what() << "\n";
  }
  owner_->mutex_.unlock();
}

nlohmann::json SiteCapture::to_json() const {
  std::lock_guard lock(mutex_);
  nlohmann::json out = {{"frame", frame_}};
  for (const Stage stage : {Stage::Sender, Stage::Receiver}) {
    const auto& path = paths_[index(stage)];
    out[stage_name(stage)] = path ? nlohmann::json(*path) : nlohmann::json();
  }
  if (!gpu_.capture_available()) out["not_taken"] = gpu_.capture_unavailable_reason();
  else if (!paths_[0] || !paths_[1]) out["not_taken"] = "the site ran fewer iterations than --capture-frame";
  return out;
}

void SiteCapture::report() const {
  if (frame_ < 0) return;
  std::lock_guard lock(mutex_);
  for (const Stage stage : {Stage::Sender, Stage::Receiver}) {
    const auto& path = paths_[index(stage)];
    if (path) std::cout << "RenderDoc capture of site " << site_name_ << "'s " << stage_name(stage) << " at frame " << frame_ << ": " << *path << "\n";
    else if (!gpu_.capture_available()) std::cout << "no capture taken of the " << stage_name(stage) << ": " << gpu_.capture_unavailable_reason() << "\n";
    else std::cout << "no capture taken of the " << stage_name(stage) << ": it ran fewer than " << frame_ + 1 << " iterations\n";
  }
}

}  // namespace rt::site
