#include "passes/common/ibr_scene.h"

#include <opencv2/calib3d.hpp>

#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>

#include "passes/common/lens.h"

namespace rt::passes {
namespace {

std::array<float, 16> column_major(const Eigen::Matrix4d& m) {
  std::array<float, 16> out{};
  for (int column = 0; column < 4; ++column)
    for (int row = 0; row < 4; ++row) out[size_t(column * 4 + row)] = float(m(row, column));
  return out;
}

bool same_size(const CameraIntrinsics& a, const CameraIntrinsics& b) { return a.width == b.width && a.height == b.height; }

}  // namespace

shader_abi::IbrLens lens_of(const CameraIntrinsics& k) {
  const Distortion& d = k.distortion;
  return {.pinhole = {float(k.fx), float(k.fy), float(k.cx), float(k.cy)},
          .radial = {float(d.k1), float(d.k2), float(d.k3), 0.0f},
          .rational = {float(d.k4), float(d.k5), float(d.k6), 0.0f},
          .tangential = {float(d.p1), float(d.p2), float(k.width), float(k.height)}};
}

IbrSceneTable make_scene_table(const Camera& target, std::span<const IbrCameraModel> cameras) {
  if (cameras.empty() || cameras.size() > RT_IBR_MAX_VIEWS)
    throw std::invalid_argument("image-based model: needs 1 to " + std::to_string(RT_IBR_MAX_VIEWS) + " cameras, got " +
                                std::to_string(cameras.size()));
  IbrSceneTable table;
  table.target.camera_from_site = column_major(target.camera_from_site.matrix());
  table.target.site_from_camera = column_major(target.camera_from_site.inverse().matrix());
  const CameraIntrinsics& t = target.intrinsics;
  table.target.pinhole = {float(t.fx), float(t.fy), float(t.cx), float(t.cy)};
  table.target.size = {float(t.width), float(t.height), 0.0f, 0.0f};
  for (size_t i = 0; i < cameras.size(); ++i) {
    const IbrCameraModel& camera = cameras[i];
    const std::string who = "image-based model: camera '" + camera.color.name + "'";
    if (!same_size(camera.color.intrinsics, cameras[0].color.intrinsics) ||
        !same_size(camera.depth.intrinsics, cameras[0].depth.intrinsics))
      throw std::invalid_argument(who + ": every camera's color images, and every depth image, must have one size");
    if (!camera.color.camera_from_site.isApprox(camera.depth.camera_from_site, 1e-9))
      throw std::invalid_argument(who + ": color and depth must share one pose");
    table.cameras[i] = {.camera_from_site = column_major(camera.color.camera_from_site.matrix()),
                        .site_from_camera = column_major(camera.color.camera_from_site.inverse().matrix()),
                        .color = lens_of(camera.color.intrinsics),
                        .depth = lens_of(camera.depth.intrinsics)};
  }
  table.camera_count = uint32_t(cameras.size());
  return table;
}

namespace {
constexpr size_t kTableBytes = sizeof(shader_abi::IbrTarget) + RT_IBR_MAX_VIEWS * sizeof(shader_abi::IbrCamera);
}

IbrSceneBuffer::IbrSceneBuffer(vk::Context& context)
    // Bound as a uniform buffer or a storage buffer, as each shader declares it
    // (shaders/common/ibr_camera.glsl says why).
    : buffer_(context, {.name = "ibr camera table",
                        .size = kTableBytes,
                        .usage = VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT | VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                        .host_visible = true}) {
  write(IbrSceneTable{});
}

void IbrSceneBuffer::write(const IbrSceneTable& table) {
  std::byte* out = buffer_.mapped();
  std::memcpy(out, &table.target, sizeof(table.target));
  std::memcpy(out + sizeof(table.target), table.cameras.data(), sizeof(shader_abi::IbrCamera) * RT_IBR_MAX_VIEWS);
}

HostImage depth_ray_atlas(std::span<const IbrCameraModel> cameras) {
  std::vector<HostImage> bands;
  for (const IbrCameraModel& camera : cameras) {
    const CameraIntrinsics& k = camera.depth.intrinsics;
    std::vector<cv::Point2d> pixels;
    pixels.reserve(size_t(k.width) * k.height);
    for (uint32_t y = 0; y < k.height; ++y)
      for (uint32_t x = 0; x < k.width; ++x) pixels.emplace_back(x, y);
    std::vector<cv::Point2d> normalised;
    const cv::Matx33d camera_matrix(k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1);
    const auto coefficients = k.distortion.as_opencv();
    cv::undistortPoints(pixels, normalised, camera_matrix, std::vector<double>(coefficients.begin(), coefficients.end()));
    const Eigen::Matrix3d site_from_camera = camera.depth.camera_from_site.inverse().rotation();
    HostImage rays(k.width, k.height, PixelFormat::RGBA32F);
    for (size_t i = 0; i < normalised.size(); ++i) {
      const cv::Point2d& n = normalised[i];
      if (!std::isfinite(n.x) || !std::isfinite(n.y)) continue;
      const Eigen::Vector3d direction = site_from_camera * Eigen::Vector3d(n.x, n.y, 1.0);
      float* ray = &rays.texels[i * 4];
      for (int c = 0; c < 3; ++c) ray[c] = float(direction[c]);
      ray[3] = 1.0f;
    }
    bands.push_back(std::move(rays));
  }
  return stack_bands(bands);
}

HostImage stack_bands(std::span<const HostImage> images) {
  if (images.empty()) throw std::invalid_argument("stack_bands: no images");
  const HostImage& first = images[0];
  HostImage atlas(first.width, first.height * uint32_t(images.size()), first.format);
  size_t offset = 0;
  for (const HostImage& image : images) {
    if (image.width != first.width || image.height != first.height || image.format != first.format)
      throw std::invalid_argument("stack_bands: images differ in size or format");
    std::copy(image.texels.begin(), image.texels.end(), atlas.texels.begin() + std::ptrdiff_t(offset));
    offset += image.texels.size();
  }
  return atlas;
}

HostImage band_of(const HostImage& atlas, uint32_t band, uint32_t band_height) {
  HostImage out(atlas.width, band_height, atlas.format);
  const size_t count = out.texels.size();
  std::copy_n(atlas.texels.begin() + std::ptrdiff_t(band * count), count, out.texels.begin());
  return out;
}

Float3 transform_point(const std::array<float, 16>& m, Float3 p) {
  return {m[0] * p.x + m[4] * p.y + m[8] * p.z + m[12], m[1] * p.x + m[5] * p.y + m[9] * p.z + m[13],
          m[2] * p.x + m[6] * p.y + m[10] * p.z + m[14]};
}

Float2 lens_pixel(const shader_abi::IbrLens& lens, Float2 xy) {
  const float r2 = xy.x * xy.x + xy.y * xy.y;
  const float numerator = 1.0f + r2 * (lens.radial[0] + r2 * (lens.radial[1] + r2 * lens.radial[2]));
  const float denominator = 1.0f + r2 * (lens.rational[0] + r2 * (lens.rational[1] + r2 * lens.rational[2]));
  const float radial = numerator / denominator;
  const float p1 = lens.tangential[0], p2 = lens.tangential[1];
  const float dx = xy.x * radial + (2.0f * p1 * xy.x * xy.y + p2 * (r2 + 2.0f * xy.x * xy.x));
  const float dy = xy.y * radial + (p1 * (r2 + 2.0f * xy.y * xy.y) + 2.0f * p2 * xy.x * xy.y);
  return {lens.pinhole[0] * dx + lens.pinhole[2], lens.pinhole[1] * dy + lens.pinhole[3]};
}

Float2 lens_project(const shader_abi::IbrLens& lens, Float3 p) { return lens_pixel(lens, {p.x / p.z, p.y / p.z}); }

bool inside_image(Float2 pixel, Float2 size, float margin) {
  return pixel.x >= -0.5f + margin && pixel.y >= -0.5f + margin && pixel.x < size.x - 0.5f - margin &&
         pixel.y < size.y - 0.5f - margin;
}

float length(Float3 v) { return std::sqrt(v.x * v.x + v.y * v.y + v.z * v.z); }

std::array<float, 3> bilinear_rgb(const HostImage& atlas, Float2 at, uint32_t band_row, uint32_t width, uint32_t height) {
  const float bx = std::floor(at.x), by = std::floor(at.y);
  const float fx = at.x - bx, fy = at.y - by;
  auto texel = [&](int x, int y, int c) {
    x = std::clamp(x, 0, int(width) - 1);
    y = std::clamp(y, 0, int(height) - 1);
    return atlas.at(uint32_t(x), uint32_t(y) + band_row, uint32_t(c));
  };
  std::array<float, 3> out{};
  for (int c = 0; c < 3; ++c) {
    const int x = int(bx), y = int(by);
    const float top = texel(x, y, c) + (texel(x + 1, y, c) - texel(x, y, c)) * fx;
    const float bottom = texel(x, y + 1, c) + (texel(x + 1, y + 1, c) - texel(x, y + 1, c)) * fx;
    out[size_t(c)] = top + (bottom - top) * fy;
  }
  return out;
}

bool view_sees(const HostImage& points, uint32_t view, uint32_t depth_height, Float2 depth_pixel, float z,
               VisibilityTolerance tolerance) {
  const int x = int(std::floor(depth_pixel.x + 0.5f)), y = int(std::floor(depth_pixel.y + 0.5f));
  const float own = points.at(uint32_t(x), uint32_t(y) + view * depth_height, 3);
  return own > 0.0f && std::abs(z - own) <= tolerance.metres + tolerance.relative * own;
}

}  // namespace rt::passes
