#pragma once
// The default site cut to `cameras` cameras at 720p colour and 2x2-binned NFOV depth (k4a modes),
// for the tests that write and play k4a recordings.
#include "config/assets.h"
#include "sim/site_description.h"

namespace rt::test {

inline sim::SiteDescription k4a_mode_site(size_t cameras) {
  sim::SiteDescription site = sim::load_site(config::assets_dir() / "sites" / "default.json");
  site.cameras.resize(cameras);
  for (sim::RgbdCamera& camera : site.cameras) {
    camera.color.width = 1280, camera.color.height = 720;
    camera.color.fx = camera.color.fy = 610, camera.color.cx = 639.5, camera.color.cy = 359.5;
    camera.depth.width = 320, camera.depth.height = 288;
    camera.depth.fx = camera.depth.fy = 252, camera.depth.cx = 159.5, camera.depth.cy = 143.5;
  }
  return site;
}

}  // namespace rt::test
