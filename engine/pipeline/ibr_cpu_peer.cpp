#include "pipeline/ibr_cpu_peer.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

namespace rt::pipeline {
namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// What one view contributes before sampling: where each target pixel lands in its colour and
// depth images, the point's depth in the camera, and the penalties and feather of ibr_warp.
struct ViewMaps {
  cv::Mat color_map, depth_map;  // CV_32FC2
  cv::Mat z, angle, resolution, feather;  // CV_32F
  cv::Mat projects;  // CV_8U: 255 where the point projects inside both images
};

ViewMaps view_maps(const passes::IbrSceneTable& table, uint32_t view, const cv::Mat& fused_depth,
                   const passes::WarpSettings& warp) {
  const int width = fused_depth.cols, height = fused_depth.rows;
  ViewMaps m{cv::Mat(height, width, CV_32FC2, cv::Scalar(-1, -1)), cv::Mat(height, width, CV_32FC2, cv::Scalar(-1, -1)),
             cv::Mat::zeros(height, width, CV_32F),  cv::Mat::zeros(height, width, CV_32F),
             cv::Mat::zeros(height, width, CV_32F),  cv::Mat::zeros(height, width, CV_32F),
             cv::Mat::zeros(height, width, CV_8U)};
  const shader_abi::IbrTarget& target = table.target;
  const shader_abi::IbrCamera& camera = table.cameras[view];
  const passes::Float2 color_size{camera.color.tangential[2], camera.color.tangential[3]};
  const passes::Float2 depth_size{camera.depth.tangential[2], camera.depth.tangential[3]};
  const passes::Float3 eye = passes::transform_point(target.site_from_camera, {0, 0, 0});
  const passes::Float3 centre = passes::transform_point(camera.site_from_camera, {0, 0, 0});
  cv::parallel_for_(cv::Range(0, height), [&](const cv::Range& rows) {
    for (int y = rows.start; y < rows.end; ++y) {
      const float* depth = fused_depth.ptr<float>(y);
      auto* color_map = m.color_map.ptr<cv::Vec2f>(y);
      auto* depth_map = m.depth_map.ptr<cv::Vec2f>(y);
      for (int x = 0; x < width; ++x) {
        const float z = depth[x];
        if (!(z > 0.0f)) continue;
        const passes::Float3 site = passes::transform_point(
            target.site_from_camera, {(float(x) - target.pinhole[2]) / target.pinhole[0] * z,
                                      (float(y) - target.pinhole[3]) / target.pinhole[1] * z, z});
        const passes::Float3 q = passes::transform_point(camera.camera_from_site, site);
        if (!(q.z > 1e-4f)) continue;
        const passes::Float2 color_pixel = passes::lens_project(camera.color, q);
        const passes::Float2 depth_pixel = passes::lens_project(camera.depth, q);
        if (!passes::inside_image(color_pixel, color_size, 0.0f) || !passes::inside_image(depth_pixel, depth_size, 0.0f))
          continue;
        const passes::Float3 to_eye{site.x - eye.x, site.y - eye.y, site.z - eye.z};
        const passes::Float3 to_camera{site.x - centre.x, site.y - centre.y, site.z - centre.z};
        const float cosine = (to_eye.x * to_camera.x + to_eye.y * to_camera.y + to_eye.z * to_camera.z) /
                             std::max(passes::length(to_eye) * passes::length(to_camera), 1e-12f);
        const float border = std::min(std::min(color_pixel.x + 0.5f, color_size.x - 0.5f - color_pixel.x),
                                      std::min(color_pixel.y + 0.5f, color_size.y - 0.5f - color_pixel.y));
        color_map[x] = {color_pixel.x, color_pixel.y};
        depth_map[x] = {depth_pixel.x, depth_pixel.y};
        m.z.ptr<float>(y)[x] = q.z;
        m.angle.ptr<float>(y)[x] = std::acos(std::clamp(cosine, -1.0f, 1.0f));
        m.resolution.ptr<float>(y)[x] = std::max(0.0f, passes::length(to_camera) - passes::length(to_eye));
        m.feather.ptr<float>(y)[x] = std::clamp(border / warp.feather_px, 1e-3f, 1.0f);
        m.projects.ptr<uint8_t>(y)[x] = 255;
      }
    }
  });
  return m;
}

}  // namespace

IbrCpuPeerInputs cpu_peer_inputs(const passes::IbrSceneTable& table, const HostImage& fused_depth,
                                 const HostImage& color_atlas, const HostImage& points_atlas) {
  if (table.camera_count == 0) throw std::invalid_argument("ibr cpu peer: no views");
  IbrCpuPeerInputs in{table, cv::Mat(int(fused_depth.height), int(fused_depth.width), CV_32F), {}, {}};
  for (uint32_t y = 0; y < fused_depth.height; ++y)
    for (uint32_t x = 0; x < fused_depth.width; ++x) in.fused_depth.at<float>(int(y), int(x)) = fused_depth.at(x, y);
  const uint32_t color_height = color_atlas.height / table.camera_count;
  const uint32_t depth_height = points_atlas.height / table.camera_count;
  for (uint32_t v = 0; v < table.camera_count; ++v) {
    cv::Mat color(int(color_height), int(color_atlas.width), CV_8UC4);
    for (uint32_t y = 0; y < color_height; ++y)
      for (uint32_t x = 0; x < color_atlas.width; ++x)
        for (uint32_t c = 0; c < 4; ++c)
          color.at<cv::Vec4b>(int(y), int(x))[int(c)] =
              cv::saturate_cast<uint8_t>(std::lround(color_atlas.at(x, y + v * color_height, c) * 255.0f));
    cv::Mat own(int(depth_height), int(points_atlas.width), CV_32F);
    for (uint32_t y = 0; y < depth_height; ++y)
      for (uint32_t x = 0; x < points_atlas.width; ++x) own.at<float>(int(y), int(x)) = points_atlas.at(x, y + v * depth_height, 3);
    in.colors.push_back(color);
    in.own_depth.push_back(own);
  }
  return in;
}

IbrCpuPeerResult run_ibr_cpu_peer(const IbrCpuPeerInputs& in, const passes::WarpSettings& warp,
                                  const passes::BlendSettings& blend) {
  const uint32_t views = in.table.camera_count;
  if (views == 0 || in.colors.size() != views || in.own_depth.size() != views)
    throw std::invalid_argument("ibr cpu peer: the inputs do not hold one colour and one depth image per view");
  const cv::Size size = in.fused_depth.size();
  IbrCpuPeerResult result;

  auto start = Clock::now();
  std::vector<ViewMaps> maps;
  for (uint32_t v = 0; v < views; ++v) maps.push_back(view_maps(in.table, v, in.fused_depth, warp));
  result.times.maps_ms = ms_since(start);

  start = Clock::now();
  std::vector<cv::Mat> colors(views), own(views);
  for (uint32_t v = 0; v < views; ++v) {
    cv::remap(in.colors[v], colors[v], maps[v].color_map, cv::noArray(), cv::INTER_LINEAR, cv::BORDER_REPLICATE);
    cv::remap(in.own_depth[v], own[v], maps[v].depth_map, cv::noArray(), cv::INTER_NEAREST, cv::BORDER_CONSTANT, 0);
  }
  result.times.sample_ms = ms_since(start);

  // The lumigraph weights of ibr_blend, a whole image at a time. Penalties of views that do not
  // see a pixel are "none" (a large number) for the k-th smallest and -1 for the largest.
  start = Clock::now();
  constexpr float kNone = 1e30f;
  std::vector<cv::Mat> visible(views), penalty(views), sorted(views);
  cv::Mat count = cv::Mat::zeros(size, CV_32F), largest = cv::Mat::zeros(size, CV_32F);
  for (uint32_t v = 0; v < views; ++v) {
    const cv::Mat& o = own[v];
    visible[v] = maps[v].projects & (o > 0.0f) &
                 (cv::abs(maps[v].z - o) <= warp.visibility.metres + o * warp.visibility.relative);
    cv::Mat p = maps[v].angle + blend.resolution_weight * maps[v].resolution;
    penalty[v] = cv::Mat(size, CV_32F, cv::Scalar(kNone));
    p.copyTo(penalty[v], visible[v]);
    cv::Mat seen;
    visible[v].convertTo(seen, CV_32F, 1.0 / 255.0);
    count += seen;
    cv::Mat for_largest(size, CV_32F, cv::Scalar(-1.0f));
    p.copyTo(for_largest, visible[v]);
    largest = cv::max(largest, for_largest);
    sorted[v] = penalty[v].clone();
  }
  for (uint32_t pass = 0; pass < views; ++pass)  // a sorting network over the views
    for (uint32_t v = 0; v + 1 < views; ++v) {
      cv::Mat low = cv::min(sorted[v], sorted[v + 1]), high = cv::max(sorted[v], sorted[v + 1]);
      sorted[v] = low;
      sorted[v + 1] = high;
    }
  const int k = blend.best_views;
  cv::Mat threshold = largest * 1.0001f + 1e-6f;
  if (k >= 1 && uint32_t(k) <= views) sorted[size_t(k - 1)].copyTo(threshold, count >= float(k));

  cv::Mat weight_sum = cv::Mat::zeros(size, CV_32F), color_sum = cv::Mat::zeros(size, CV_32FC3);
  std::vector<cv::Mat> rgb(views);
  for (uint32_t v = 0; v < views; ++v) {
    cv::Mat rgba;
    colors[v].convertTo(rgba, CV_32FC4, 1.0 / 255.0);
    cv::cvtColor(rgba, rgb[v], cv::COLOR_RGBA2RGB);
    cv::Mat w = cv::max(1.0f - penalty[v] / threshold, 0.0f).mul(maps[v].feather);
    maps[v].feather.copyTo(w, threshold <= 0.0f);
    w.setTo(0.0f, ~visible[v]);
    weight_sum += w;
    cv::Mat w3;
    cv::merge(std::vector<cv::Mat>{w, w, w}, w3);
    color_sum += rgb[v].mul(w3);
  }
  cv::Mat weight3;
  cv::merge(std::vector<cv::Mat>{weight_sum, weight_sum, weight_sum}, weight3);
  cv::Mat color = color_sum / weight3;
  // Every weight zero happens only where the best views tie with the threshold: the best view.
  std::vector<cv::Point> ties;
  cv::findNonZero((count > 0.0f) & (weight_sum <= 1e-6f), ties);
  for (const cv::Point& p : ties)
    for (uint32_t v = 0; v < views; ++v)
      if (penalty[v].at<float>(p) == sorted[0].at<float>(p)) {
        color.at<cv::Vec3f>(p) = rgb[v].at<cv::Vec3f>(p);
        break;
      }
  cv::Mat alpha;
  cv::Mat(count > 0.0f).convertTo(alpha, CV_32F, 1.0 / 255.0);
  color.setTo(cv::Scalar::all(0), count <= 0.0f);
  cv::Mat channels[4];
  cv::split(color, channels);
  channels[3] = alpha;
  cv::merge(channels, 4, result.portrait);
  result.portrait = cv::min(cv::max(result.portrait, 0.0f), 1.0f);
  result.times.blend_ms = ms_since(start);
  return result;
}

}  // namespace rt::pipeline
