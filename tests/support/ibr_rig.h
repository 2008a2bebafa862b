#pragma once
// A small image-based-model rig for the IBR pass tests: RGBD cameras around the site's user
// volume looking at it (with a slight lens distortion), the target view of a remote eye, and
// random but plausible inputs (depths on a bumpy surface in front of the cameras, with holes).
#include <random>
#include <vector>

#include "passes/common/ibr_scene.h"
#include "passes/ibr_tiles.h"

namespace rt::test {

struct IbrRig {
  std::vector<passes::IbrCameraModel> cameras;
  Camera target;
  passes::IbrSceneTable table;
};

// `views` cameras with color and depth images of the given sizes; target of the given size.
IbrRig ibr_rig(uint32_t views, uint32_t color_w, uint32_t color_h, uint32_t depth_w, uint32_t depth_h,
               uint32_t target_w, uint32_t target_h, bool distortion = true);

// `rig` with every camera turned to look straight ahead (+z, away from the eye), where the
// target's surface lies behind all of them.
IbrRig turned_away(IbrRig rig);

// R16U atlas: each view sees a surface about 0.5-0.9 m away; `hole_fraction` of pixels are 0.
HostImage random_depth_atlas(std::mt19937& rng, const IbrRig& rig, float hole_fraction = 0.1f);

// R32F target-view depth of a surface 1.3-1.5 m from the eye, 15% of pixels holes (0).
HostImage random_fused_depth(std::mt19937& rng, uint32_t width, uint32_t height);

// The tiles `tiles` lists on the GPU (read back), sorted as passes::ibr_tiles_reference sorts them.
std::vector<passes::TileIndex> listed_tiles(passes::IbrTiles& tiles);
// Writes `listed` and its dispatch into `tiles`, for a pass that runs over a list made elsewhere.
void upload_tiles(passes::IbrTiles& tiles, const std::vector<passes::TileIndex>& listed);

}  // namespace rt::test
