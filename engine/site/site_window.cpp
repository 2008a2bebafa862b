#include "site/site_window.h"

#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <cstdio>
#include <iostream>

#include "display/glfw_window.h"
#include "site/site_display.h"
#include "time/monotonic_clock.h"

namespace rt::site {
namespace {

// Depth shown from white (near) to black (far) over the range a user at a site stands in.
constexpr float kNearestShownM = 0.3f, kFarthestShownM = 2.5f;
// The angle penalty (radians) above which a view gets no weight in any blend we run.
constexpr float kLargestShownPenaltyRad = 0.5f;

// The sender's image a pass wrote under this name, or none.
vk::Image* sender_image(const SiteCommon& common, const std::string& name) {
  if (!common.sender_graph) return nullptr;
  for (const auto& [pass, image] : common.sender_graph->written_images())
    if (image->name() == name) return image;
  return nullptr;
}

}  // namespace

SiteWindowDisplay::SiteWindowDisplay(SiteCommon& common, const ReceiverImages& images)
    : common_(common),
      images_(images),
      presenter_(std::make_unique<display::WindowPresenter>(*common.context, *common.window,
                                                            display::parse_present_mode(common.options.present_mode))) {}

SiteWindowDisplay::~SiteWindowDisplay() = default;

SiteWindowDisplay::View SiteWindowDisplay::current_view() const {
  const uint32_t views = std::max(common_.options.ibr.views, 1u);
  auto band_of = [&](vk::Image* atlas, passes::DisplayViewMapping mapping) {
    if (atlas) {
      mapping.band_height = atlas->height() / views;
      mapping.band_y0 = (band_ % views) * mapping.band_height;
    }
    return mapping;
  };
  passes::DisplayViewMapping color;
  passes::DisplayViewMapping depth{.mode = RT_VIEW_DEPTH, .low = kNearestShownM, .high = kFarthestShownM};
  passes::DisplayViewMapping unit{.mode = RT_VIEW_CHANNEL};
  passes::DisplayViewMapping penalty{.mode = RT_VIEW_CHANNEL, .low = 0.0f, .high = kLargestShownPenaltyRad};
  const std::string view_number = " of view " + std::to_string(band_ % views + 1) + "/" + std::to_string(views);
  switch (view_) {
    case 0: return {"fused depth", sender_image(common_, "ibr fused depth"), depth};
    case 1: {
      vk::Image* warped = sender_image(common_, "ibr warped");
      return {"warp" + view_number, warped, band_of(warped, color)};
    }
    case 2: {
      vk::Image* features = sender_image(common_, "ibr features");
      return {"blend penalty" + view_number, features, band_of(features, penalty)};
    }
    case 3: return {"hand mask", &images_.hand_mask, unit};
    case 4: return {"hand alpha", &images_.hand_alpha, unit};
    case 5: return {"hand render", &images_.hand_color, color};
    case 6: return {"portrait", &images_.portrait, color};
    default: return {"composite", &images_.composite, color};
  }
}

bool SiteWindowDisplay::take_keys() {
  bool redraw = false;
  for (const display::WindowCommand command : common_.window->take_commands()) {
    if (command == display::WindowCommand::Pause) {
      paused_ = !paused_;
      common_.events->write("window", monotonic_now_us(), {{"paused", paused_}});
    } else if (command == display::WindowCommand::Screenshot) {
      screenshot_requested_ = redraw = true;
    } else if (const int index = display::view_index(command); index >= 0) {
      // F2 and F3 again: the next camera view of the same image.
      if (index == view_ && (index == 1 || index == 2)) ++band_;
      else band_ = 0;
      view_ = index;
      ++views_chosen_;
      redraw = view_changed_ = true;
      const View view = current_view();
      if (std::find(views_seen_.begin(), views_seen_.end(), view.label) == views_seen_.end()) views_seen_.push_back(view.label);
      common_.events->write("window", monotonic_now_us(), {{"view", view.label}});
    }
  }
  return redraw;
}

void SiteWindowDisplay::present() {
  View view = current_view();
  if (!view.image) {  // this run has no such image: say so on the composite
    const bool per_view = view_ == 1 || view_ == 2;
    std::cerr << "site " << common_.name << ": window: no " << view.label << " in this run"
              << (per_view ? " (warp and blend ran as one pass; --split-warp keeps each view's warp)" : "")
              << ", showing the composite\n";
    view_ = 7;
    view = current_view();
  }
  presenter_->present(*view.image, view.mapping);
}

void SiteWindowDisplay::show_frame(uint64_t display_index) {
  if (paused_) {
    ++frames_held_by_pause_;
    if (view_changed_) present();  // another view, of this moment, even while the composite holds
    view_changed_ = false;
  } else {
    present();
    view_changed_ = false;
    shown_display_index_ = display_index;
  }
  if (screenshot_requested_) write_screenshot();
}

void SiteWindowDisplay::refresh() {
  // A screenshot alone needs no drawing: the view on screen is the last one presented.
  if (view_changed_) present();
  view_changed_ = false;
  if (screenshot_requested_) write_screenshot();
}

void SiteWindowDisplay::write_screenshot() {
  screenshot_requested_ = false;
  const HostImage view = presenter_->last_view();
  if (view.width == 0) return;
  std::filesystem::create_directories(common_.out / "screenshots");
  char name[48];
  std::snprintf(name, sizeof name, "window_%04llu.png", static_cast<unsigned long long>(screenshots_++));
  const std::filesystem::path file = common_.out / "screenshots" / name;
  cv::imwrite(file.string(), to_bgr8(view));
  common_.events->write("screenshot", monotonic_now_us(),
                        {{"file", file.filename().string()},
                         {"view", current_view().label},
                         {"display", shown_display_index_ ? nlohmann::json(*shown_display_index_) : nlohmann::json()},
                         {"width", view.width},
                         {"height", view.height}});
  std::cerr << "site " << common_.name << ": window: screenshot " << file.string() << "\n";
}

nlohmann::json SiteWindowDisplay::metrics() const {
  const display::PresenterCounts& counts = presenter_->counts();
  return {{"window", common_.window->description()},
          {"present_mode", presenter_->present_mode_name()},
          {"presented", counts.presented},
          {"skipped_minimised", counts.skipped_minimised},
          {"skipped_not_ready", counts.skipped_not_ready},
          {"swapchains_made", counts.swapchains_made},
          {"surfaces_lost", counts.surfaces_lost},
          {"frames_held_by_pause", frames_held_by_pause_},
          {"views_chosen", views_chosen_},
          {"views_seen", views_seen_},
          {"screenshots", screenshots_}};
}

}  // namespace rt::site
