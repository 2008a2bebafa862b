#include "support/ibr_rig.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <span>
#include <tuple>

#include "geometry/target_view.h"
#include "sim/default_site.h"
#include "support/gpu_test.h"

namespace rt::test {
namespace {

CameraIntrinsics intrinsics(uint32_t w, uint32_t h, double horizontal_fov_deg, bool distortion) {
  CameraIntrinsics k;
  k.width = w;
  k.height = h;
  k.fx = k.fy = 0.5 * w / std::tan(horizontal_fov_deg * M_PI / 360.0);
  k.cx = 0.5 * w - 0.5;
  k.cy = 0.5 * h - 0.5;
  if (distortion) k.distortion = {.k1 = -0.05, .k2 = 0.01, .p1 = 0.001, .p2 = -0.0005};
  return k;
}

}  // namespace

IbrRig ibr_rig(uint32_t views, uint32_t color_w, uint32_t color_h, uint32_t depth_w, uint32_t depth_h,
               uint32_t target_w, uint32_t target_h, bool distortion) {
  // Around the screen's edges, as the site's stand, looking at the user's chest.
  const Eigen::Vector3d mounts[RT_IBR_MAX_VIEWS] = {{-0.72, 0.40, 0.05}, {0.0, 0.40, 0.05}, {0.72, 0.40, 0.05},
                                                    {-0.72, -0.40, 0.05}, {0.0, -0.40, 0.05}, {0.72, -0.40, 0.05}};
  const Eigen::Vector3d chest(0.0, 0.0, 0.7);
  IbrRig rig;
  for (uint32_t v = 0; v < views; ++v) {
    passes::IbrCameraModel camera;
    camera.color.name = "camera " + std::to_string(v);
    camera.color.intrinsics = intrinsics(color_w, color_h, 90.0, distortion);
    camera.color.camera_from_site = sim::camera_from_site_looking_at(mounts[v % RT_IBR_MAX_VIEWS], chest);
    camera.depth = camera.color;
    camera.depth.intrinsics = intrinsics(depth_w, depth_h, 100.0, distortion);
    rig.cameras.push_back(camera);
  }
  rig.target = target_view_camera(Eigen::Vector3d(0.05, 0.1, -0.7), Screen{}, target_w, target_h);
  rig.table = passes::make_scene_table(rig.target, rig.cameras);
  return rig;
}

HostImage random_depth_atlas(std::mt19937& rng, const IbrRig& rig, float hole_fraction) {
  std::vector<HostImage> bands;
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (const auto& camera : rig.cameras) {
    const uint32_t w = camera.depth.intrinsics.width, h = camera.depth.intrinsics.height;
    HostImage depth(w, h, PixelFormat::R16U);
    const float phase = unit(rng) * 6.0f;
    for (uint32_t y = 0; y < h; ++y)
      for (uint32_t x = 0; x < w; ++x) {
        if (unit(rng) < hole_fraction) continue;
        // A smooth, bumpy surface with a step: both gentle slopes and depth edges.
        const float base = 700.0f + 150.0f * std::sin(0.3f * float(x) + phase) * std::cos(0.2f * float(y));
        const float step = (x + y) % 11 < 3 ? -200.0f : 0.0f;
        depth.at(x, y) = std::round(base + step + unit(rng) * 4.0f);
      }
    bands.push_back(std::move(depth));
  }
  return passes::stack_bands(bands);
}

HostImage random_fused_depth(std::mt19937& rng, uint32_t width, uint32_t height) {
  HostImage depth(width, height, PixelFormat::R32F);
  std::uniform_real_distribution<float> z(1.3f, 1.5f), unit(0.0f, 1.0f);
  for (float& texel : depth.texels) texel = z(rng);
  for (float& texel : depth.texels)
    if (unit(rng) < 0.15f) texel = 0.0f;
  return depth;
}

IbrRig turned_away(IbrRig rig) {
  for (auto& camera : rig.cameras) {
    const Eigen::Vector3d position = camera.depth.position_in_site();
    camera.depth.camera_from_site = sim::camera_from_site_looking_at(position, position + Eigen::Vector3d::UnitZ());
    camera.color.camera_from_site = camera.depth.camera_from_site;
  }
  rig.table = passes::make_scene_table(rig.target, rig.cameras);
  return rig;
}

std::vector<passes::TileIndex> listed_tiles(passes::IbrTiles& tiles) {
  const std::vector<std::byte> dispatch = vk::download(test::gpu(), tiles.dispatch());
  uint32_t count = 0;
  std::memcpy(&count, dispatch.data(), sizeof count);
  const std::vector<std::byte> bytes = vk::download(test::gpu(), tiles.tiles());
  std::vector<std::array<uint32_t, 4>> entries(std::min<size_t>(count, bytes.size() / 16));
  std::memcpy(entries.data(), bytes.data(), entries.size() * 16);
  std::vector<passes::TileIndex> listed;
  for (const auto& e : entries) listed.push_back({e[0], e[1], e[2]});
  std::sort(listed.begin(), listed.end(), [](const passes::TileIndex& a, const passes::TileIndex& b) {
    return std::tie(a[2], a[1], a[0]) < std::tie(b[2], b[1], b[0]);
  });
  return listed;
}

void upload_tiles(passes::IbrTiles& tiles, const std::vector<passes::TileIndex>& listed) {
  std::vector<uint32_t> entries;
  for (const auto& t : listed) entries.insert(entries.end(), {t[0], t[1], t[2], 0u});
  entries.resize(std::max<size_t>(entries.size(), tiles.tiles().size() / sizeof(uint32_t)), 0u);
  entries.resize(tiles.tiles().size() / sizeof(uint32_t));
  vk::upload(test::gpu(), tiles.tiles(), std::as_bytes(std::span(entries)));
  const std::array<uint32_t, 3> dispatch{uint32_t(listed.size()), 1, 1};
  vk::upload(test::gpu(), tiles.dispatch(), std::as_bytes(std::span(dispatch)));
}

}  // namespace rt::test
