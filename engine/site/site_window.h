#pragma once
// What a site's window shows (the display thread's side of it): the newest composite, or one of
// the debug views F1-F8 pick (fused depth, each view's warp, each view's blend penalty, the hand
// mask, the hand alpha, the hand render, the portrait, the composite); P holds the picture still,
// S writes what the screen shows to screenshots/. Pressing F2 or F3 again steps to the next view.
#include <nlohmann/json.hpp>

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "display/window_presenter.h"
#include "site/site_common.h"

namespace rt::site {

struct ReceiverImages {
  vk::Image& portrait;
  vk::Image& hand_mask;
  vk::Image& hand_alpha;
  vk::Image& hand_color;
  vk::Image& composite;
};

class SiteWindowDisplay {
 public:
  // Under the GPU turn (it makes the swapchain).
  SiteWindowDisplay(SiteCommon& common, const ReceiverImages& images);
  ~SiteWindowDisplay();

  // Without the GPU turn: takes the window's key presses; true when the screen must be drawn again
  // although no new frame came (another view, a screenshot).
  bool take_keys();
  // Under the GPU turn: a new frame was displayed (its display index), shown unless paused.
  void show_frame(uint64_t display_index);
  // Under the GPU turn: draws the current view again, for a key press between frames.
  void refresh();

  nlohmann::json metrics() const;

 private:
  struct View {
    std::string label;
    vk::Image* image = nullptr;  // null: not in this run (the sender renders no such image)
    passes::DisplayViewMapping mapping;
  };
  View current_view() const;
  void present();
  void write_screenshot();

  SiteCommon& common_;
  ReceiverImages images_;
  std::unique_ptr<display::WindowPresenter> presenter_;
  int view_ = 7;       // the composite
  uint32_t band_ = 0;  // the camera view shown by F2 and F3
  bool paused_ = false;
  bool screenshot_requested_ = false;
  bool view_changed_ = false;
  std::optional<uint64_t> shown_display_index_;
  uint64_t screenshots_ = 0, frames_held_by_pause_ = 0, views_chosen_ = 0;
  std::vector<std::string> views_seen_;
};

}  // namespace rt::site
