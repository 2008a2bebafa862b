// ibr_splat: GPU against the C++ reference. Nearest depths agree to 1e-5 relative; a splat's
// square is decided by float comparisons at pixel centres, so a pixel on the very edge of a
// square may go either way: at most 0.5% of pixels may differ in coverage (stated tolerance),
// none may be NaN. The splats run with ibr_fuse after them, as in the renderer, so that a second
// frame shows the buffer cleared; ibr_fuse itself is tested in test_ibr_fuse.cpp.
#include <bit>
#include <limits>
#include <optional>

#include "passes/ibr_foreground.h"
#include "passes/ibr_fuse.h"
#include "passes/ibr_splat.h"
#include "support/gpu_test.h"
#include "support/ibr_rig.h"
#include "support/pass_harness.h"

using namespace rt;

namespace {

struct SplatResult {
  std::vector<uint32_t> fusion;
  HostImage fused_depth;
};

SplatResult run_gpu_ibr_splat(const test::IbrRig& rig, const HostImage& points, const passes::SplatSettings& splat = {},
                    passes::FuseSettings fuse = {}) {
  fuse.fusion = splat.fusion;
  const passes::IbrSplatPass splat_pass(test::gpu(), splat);
  const passes::IbrFusePass fuse_pass(test::gpu(), fuse);
  passes::IbrSceneBuffer scene(test::gpu());
  scene.write(rig.table);
  test::PassHarness gpu("ibr_splat");
  const uint32_t tw = rig.target.intrinsics.width, th = rig.target.intrinsics.height;
  const vk::BufferDesc fusion_desc = passes::fusion_buffer_desc(tw, th);
  vk::Buffer& fusion = gpu.buffer(fusion_desc, {}, true);
  const uint32_t views = uint32_t(rig.cameras.size());
  passes::IbrTiles tiles(test::gpu(), "point tiles", points.width, points.height / views, views);
  test::upload_tiles(tiles, passes::ibr_tiles_reference(points, views, 3));
  splat_pass.add_to(gpu.graph(), scene, gpu.input("points", points), tiles, fusion, views);
  fuse_pass.add_to(gpu.graph(), fusion, gpu.output("fused depth", tw, th, PixelFormat::R32F));
  const test::PassOutputs out = gpu.run(2);  // a second frame must clear the buffer first, not accumulate
  return {out.values<uint32_t>(fusion_desc.name), out.image("fused depth")};
}

// Points from the foreground pass's reference on random depths.
HostImage random_points(std::mt19937& rng, const test::IbrRig& rig, float holes = 0.1f) {
  const HostImage depth = test::random_depth_atlas(rng, rig, holes);
  return passes::ibr_foreground_reference(rig.table, depth, passes::depth_ray_atlas(rig.cameras));
}

void require_fusion_matches(const std::vector<uint32_t>& gpu, const std::vector<uint32_t>& reference, size_t pixels) {
  size_t coverage_differs = 0, depth_differs = 0, non_finite = 0;
  for (size_t i = 0; i < pixels; ++i) {
    const bool gpu_set = gpu[i] != RT_IBR_EMPTY_DEPTH_BITS, ref_set = reference[i] != RT_IBR_EMPTY_DEPTH_BITS;
    if (gpu_set != ref_set) {
      ++coverage_differs;
      continue;
    }
    if (!gpu_set) continue;
    const float g = std::bit_cast<float>(gpu[i]), r = std::bit_cast<float>(reference[i]);
    if (!std::isfinite(g) || !(g > 0.0f)) ++non_finite;
    if (std::abs(g - r) > 1e-5f * r) ++depth_differs;  // a neighbour's splat may win on an edge pixel
  }
  INFO(coverage_differs << " coverage, " << depth_differs << " depth differences of " << pixels);
  REQUIRE(non_finite == 0);
  REQUIRE(coverage_differs <= pixels / 200);
  REQUIRE(depth_differs <= pixels / 200 + 1);
}

// The largest of error(x, y, depth) over the covered pixels of a width x height target where it
// is given, and in `counted` how many those are.
template <typename Error>
double worst_over_covered(const std::vector<uint32_t>& fusion, uint32_t width, uint32_t height, size_t& counted,
                          Error error) {
  double worst = 0;
  counted = 0;
  for (uint32_t y = 0; y < height; ++y)
    for (uint32_t x = 0; x < width; ++x) {
      const uint32_t bits = fusion[size_t(y) * width + x];
      if (bits == RT_IBR_EMPTY_DEPTH_BITS) continue;
      const std::optional<double> e = error(x, y, std::bit_cast<float>(bits));
      if (!e) continue;
      ++counted;
      worst = std::max(worst, *e);
    }
  return worst;
}

size_t covered_ibr_splat(const std::vector<uint32_t>& fusion, size_t pixels) {
  size_t count = 0;
  for (size_t i = 0; i < pixels; ++i) count += fusion[i] != RT_IBR_EMPTY_DEPTH_BITS;
  return count;
}

}  // namespace

TEST_CASE("ibr_splat min and average fusion on random views, odd target sizes", "[ibr_splat][gpu]") {
  test::NoValidationErrors no_errors;
  std::mt19937 rng(21);
  for (const auto& [width, height] : test::odd_sizes()) {
    for (auto [mode, edge_inset] : {std::pair{passes::DepthFusion::Min, 0.0f}, std::pair{passes::DepthFusion::Average, 0.0f},
                                    std::pair{passes::DepthFusion::Min, 0.3f}}) {
      INFO(width << "x" << height << (mode == passes::DepthFusion::Min ? " min" : " average") << ", edge inset "
                 << edge_inset);
      const test::IbrRig rig = test::ibr_rig(3, 16, 9, 41, 37, width, height);
      const HostImage points = random_points(rng, rig);
      passes::SplatSettings settings;
      settings.fusion = mode;
      settings.edge_inset = edge_inset;
      const SplatResult gpu = run_gpu_ibr_splat(rig, points, settings);
      const auto reference = passes::ibr_splat_reference(rig.table, points, settings);
      const size_t n = size_t(width) * height;
      require_fusion_matches(gpu.fusion, reference, n);
      if (n > 1000) REQUIRE(covered_ibr_splat(reference, n) > n / 20);  // the rig really lands in the target
      if (mode == passes::DepthFusion::Average) {
        // Counts and sums: same tolerance on coverage, sums to 1e-4 relative per sample.
        size_t differs = 0;
        for (size_t i = 0; i < n; ++i)
          if (gpu.fusion[2 * n + i] != reference[2 * n + i] ||
              std::abs(double(gpu.fusion[n + i]) - reference[n + i]) > 1e-4 * reference[n + i] + 2.0)
            ++differs;
        REQUIRE(differs <= n / 100 + 1);
      }
    }
  }
}

TEST_CASE("ibr_splat hard cases", "[ibr_splat][gpu]") {
  test::NoValidationErrors no_errors;
  const test::IbrRig rig = test::ibr_rig(2, 16, 9, 31, 29, 45, 27);
  const size_t n = 45 * 27;

  SECTION("points behind the eye are not splatted") {
    HostImage points(31, 58, PixelFormat::RGBA32F);
    for (uint32_t y = 0; y < 58; ++y)
      for (uint32_t x = 0; x < 31; ++x) {
        float* p = &points.texels[points.index(x, y)];
        p[0] = 0.001f * float(x), p[1] = 0.001f * float(y), p[2] = -1.0f, p[3] = 0.7f;  // z = -1: behind the eye at -0.7
      }
    const SplatResult gpu = run_gpu_ibr_splat(rig, points);
    REQUIRE(covered_ibr_splat(gpu.fusion, n) == 0);
    REQUIRE(covered_ibr_splat(passes::ibr_splat_reference(rig.table, points), n) == 0);
  }
  SECTION("no points at all: an empty, finite depth") {
    const HostImage points(31, 58, PixelFormat::RGBA32F, 0.0f);
    const SplatResult gpu = run_gpu_ibr_splat(rig, points);
    REQUIRE(covered_ibr_splat(gpu.fusion, n) == 0);
    RT_REQUIRE_MATCHES(gpu.fused_depth, HostImage(45, 27, PixelFormat::R32F, 0.0f), 0.0, 0.0);
  }
  SECTION("the nearest surface wins: a near point in front of a far plane") {
    HostImage points(31, 58, PixelFormat::RGBA32F, 0.0f);
    auto put = [&](uint32_t x, uint32_t y, Eigen::Vector3f site) {
      float* p = &points.texels[points.index(x, y)];
      p[0] = site.x(), p[1] = site.y(), p[2] = site.z(), p[3] = 0.7f;
    };
    put(0, 0, {0.0f, 0.1f, 0.9f});   // far (view 0)
    put(0, 29, {0.0f, 0.1f, 0.5f});  // near, same ray from the eye (view 1)
    const SplatResult gpu = run_gpu_ibr_splat(rig, points);
    const auto reference = passes::ibr_splat_reference(rig.table, points);
    require_fusion_matches(gpu.fusion, reference, n);
    float nearest = 1e9f;
    for (size_t i = 0; i < n; ++i)
      if (gpu.fusion[i] != RT_IBR_EMPTY_DEPTH_BITS) nearest = std::min(nearest, std::bit_cast<float>(gpu.fusion[i]));
    REQUIRE(nearest == Approx(1.2f).epsilon(1e-5));  // eye at z = -0.7: 0.5 + 0.7
  }
}

TEST_CASE("ibr_splat: splats of a tilted plane tile it at its own depths", "[ibr_splat][gpu]") {
  // One camera sees a disc of a plane face-on; the eye sees it at about 50 degrees. Each splat is
  // the parallelogram of its depth pixel on the plane, so every covered target pixel has the
  // plane's depth along its ray (to float precision, stated: 0.5 mm). Squares at one depth each,
  // as a splat without neighbours on the surface is drawn (plane_tolerance_m = 0), miss by
  // centimetres: the test can tell the two apart.
  test::NoValidationErrors no_errors;
  const test::IbrRig rig = test::ibr_rig(1, 16, 9, 121, 91, 321, 181, false);
  const Eigen::Vector3d centre(0.0, 0.0, 0.7);
  const Eigen::Vector3d normal = (rig.cameras[0].depth.position_in_site() - centre).normalized();
  HostImage points(121, 91, PixelFormat::RGBA32F, 0.0f);
  for (uint32_t y = 0; y < 91; ++y)
    for (uint32_t x = 0; x < 121; ++x) {
      const Camera& depth_camera = rig.cameras[0].depth;
      const Eigen::Vector3d origin = depth_camera.position_in_site(), ray = depth_camera.ray_in_site({x, y});
      const Eigen::Vector3d site = origin + ray * ((centre - origin).dot(normal) / ray.dot(normal));
      if ((site - centre).norm() > 0.15) continue;
      float* p = &points.texels[points.index(x, y)];
      p[0] = float(site.x()), p[1] = float(site.y()), p[2] = float(site.z());
      p[3] = float((depth_camera.camera_from_site * site).z());
    }
  // The plane's depth along each target pixel's ray.
  const Camera& eye = rig.target;
  auto plane_depth = [&](uint32_t x, uint32_t y) {
    const Eigen::Vector3d origin = eye.position_in_site(), ray = eye.ray_in_site({x, y});
    return (eye.camera_from_site * (origin + ray * ((centre - origin).dot(normal) / ray.dot(normal)))).z();
  };
  auto worst_error_mm = [&](const std::vector<uint32_t>& fusion, size_t& covered_pixels) {
    return worst_over_covered(fusion, 321, 181, covered_pixels, [&](uint32_t x, uint32_t y, float depth) {
      return std::optional<double>(std::abs(double(depth) - plane_depth(x, y)) * 1000.0);
    });
  };
  INFO("eye to plane: " << std::acos(std::abs(normal.dot((eye.position_in_site() - centre).normalized()))) * 180 / 3.14159
                        << " degrees");
  const SplatResult gpu = run_gpu_ibr_splat(rig, points);
  const auto reference = passes::ibr_splat_reference(rig.table, points);
  require_fusion_matches(gpu.fusion, reference, 321 * 181);
  size_t covered_gpu = 0, covered_reference = 0;
  CHECK(worst_error_mm(gpu.fusion, covered_gpu) < 0.5);
  CHECK(worst_error_mm(reference, covered_reference) < 0.5);
  CHECK(covered_reference > 500);  // the disc is about 0.3 m across
  CHECK(covered_gpu > 500);

  passes::SplatSettings squares;
  squares.plane_tolerance_m = 0.0f;
  size_t covered_squares = 0;
  CHECK(worst_error_mm(passes::ibr_splat_reference(rig.table, points, squares), covered_squares) > 5.0);

  // Pulling the outline in takes pixels off the disc's rim only: every pixel it drops borders
  // one the plain splats leave empty, the depths stay the plane's, and the GPU agrees.
  passes::SplatSettings inset;
  inset.edge_inset = 0.3f;
  const SplatResult gpu_inset = run_gpu_ibr_splat(rig, points, inset);
  const auto reference_inset = passes::ibr_splat_reference(rig.table, points, inset);
  require_fusion_matches(gpu_inset.fusion, reference_inset, 321 * 181);
  size_t covered_inset = 0;
  CHECK(worst_error_mm(reference_inset, covered_inset) < 0.5);
  auto empty = [](const std::vector<uint32_t>& fusion, int x, int y) {
    return x < 0 || y < 0 || x >= 321 || y >= 181 || fusion[size_t(y) * 321 + size_t(x)] == RT_IBR_EMPTY_DEPTH_BITS;
  };
  size_t dropped = 0, dropped_inside = 0, added = 0;
  for (int y = 0; y < 181; ++y)
    for (int x = 0; x < 321; ++x) {
      if (!empty(reference, x, y) && empty(reference_inset, x, y)) {
        ++dropped;
        bool on_rim = false;
        for (int dy = -2; dy <= 2; ++dy)
          for (int dx = -2; dx <= 2; ++dx) on_rim = on_rim || empty(reference, x + dx, y + dy);
        dropped_inside += !on_rim;
      }
      added += empty(reference, x, y) && !empty(reference_inset, x, y);
    }
  INFO(dropped << " rim pixels dropped of " << covered_reference << ", " << dropped_inside << " inside");
  CHECK(dropped > 0);
  CHECK(dropped < covered_reference / 5);
  CHECK(dropped_inside == 0);
  CHECK(added == 0);

  // A line one depth pixel wide (a thin finger) is drawn as squares, which keep their size: the
  // inset must not break it into dots.
  HostImage line(121, 91, PixelFormat::RGBA32F, 0.0f);
  for (uint32_t y = 0; y < 91; ++y)
    for (uint32_t c = 0; c < 4; ++c) line.texels[line.index(60, y) + c] = points.texels[points.index(60, y) + c];
  const auto line_plain = passes::ibr_splat_reference(rig.table, line);
  const auto line_inset = passes::ibr_splat_reference(rig.table, line, inset);
  CHECK(covered_ibr_splat(line_plain, 321 * 181) > 50);
  CHECK(line_inset == line_plain);
  require_fusion_matches(run_gpu_ibr_splat(rig, line, inset).fusion, line_inset, 321 * 181);
}

TEST_CASE("ibr_splat: splats of a curved surface stay on it, not in front of it", "[ibr_splat][gpu]") {
  // One camera sees a vertical cylinder of 3 cm radius where a depth pixel is about 1 cm (a
  // finger as the site's cameras see it: 8 mm radius, 4 mm pixels); the eye sees it from the
  // front, so the part the camera sees turns away from the eye. Each quarter of a splat lies on
  // the chords to its two neighbours, which run inside a convex surface, so away from the patch's
  // outline no covered pixel may lie in front of the cylinder along the eye's ray. One plane per
  // splat extrapolates half of it from the far neighbours, out in front of the surface (1.6 mm
  // here, measured), and the min-filter keeps such errors. Stated tolerance: 0.5 mm in front.
  test::NoValidationErrors no_errors;
  const test::IbrRig rig = test::ibr_rig(1, 16, 9, 241, 181, 641, 361, false);
  const Eigen::Vector3d axis_point(0.0, 0.0, 0.75);
  const double radius = 0.03, half_height = 0.12;
  // The nearest hit of a ray with the cylinder's side (vertical axis through axis_point).
  auto hit = [&](const Eigen::Vector3d& origin, const Eigen::Vector3d& ray) -> std::optional<Eigen::Vector3d> {
    const Eigen::Vector2d o(origin.x() - axis_point.x(), origin.z() - axis_point.z()), d(ray.x(), ray.z());
    const double a = d.squaredNorm(), b = 2.0 * o.dot(d), c = o.squaredNorm() - radius * radius;
    const double discriminant = b * b - 4.0 * a * c;
    if (discriminant < 0.0 || a <= 0.0) return std::nullopt;
    const Eigen::Vector3d site = origin + ray * ((-b - std::sqrt(discriminant)) / (2.0 * a));
    if (std::abs(site.y() - axis_point.y()) > half_height) return std::nullopt;
    return site;
  };
  const Camera& depth_camera = rig.cameras[0].depth;
  // The part of the side the camera sees at up to 55 degrees: steeper, a depth pixel's step
  // exceeds the splats' plane tolerance and the surface ends there for the splats (an outline).
  auto on_patch = [&](const Eigen::Vector3d& site) {
    const Eigen::Vector3d normal = Eigen::Vector3d(site.x() - axis_point.x(), 0.0, site.z() - axis_point.z()).normalized();
    return normal.dot((depth_camera.position_in_site() - site).normalized()) > std::cos(55.0 * M_PI / 180.0);
  };
  HostImage points(241, 181, PixelFormat::RGBA32F, 0.0f);
  for (uint32_t y = 0; y < 181; ++y)
    for (uint32_t x = 0; x < 241; ++x) {
      const auto site = hit(depth_camera.position_in_site(), depth_camera.ray_in_site({x, y}));
      if (!site || !on_patch(*site)) continue;
      float* p = &points.texels[points.index(x, y)];
      p[0] = float(site->x()), p[1] = float(site->y()), p[2] = float(site->z());
      p[3] = float((depth_camera.camera_from_site * *site).z());
    }
  // The covered pixels whose eye ray meets the patch at least two target pixels inside its outline
  // (the outline's splats extrapolate, as they must).
  const Camera& eye = rig.target;
  auto in_front_mm = [&](const std::vector<uint32_t>& fusion, size_t& tested) {
    return worst_over_covered(fusion, 641, 361, tested, [&](uint32_t x, uint32_t y, float depth) -> std::optional<double> {
      std::optional<Eigen::Vector3d> site;
      for (int dy = -2; dy <= 2; ++dy)
        for (int dx = -2; dx <= 2; ++dx) {
          const auto around = hit(eye.position_in_site(), eye.ray_in_site({double(x) + dx, double(y) + dy}));
          if (!around || !on_patch(*around)) return std::nullopt;
          if (dx == 0 && dy == 0) site = around;
        }
      return ((eye.camera_from_site * *site).z() - double(depth)) * 1000.0;
    });
  };
  const SplatResult gpu = run_gpu_ibr_splat(rig, points);
  const auto reference = passes::ibr_splat_reference(rig.table, points);
  require_fusion_matches(gpu.fusion, reference, 641 * 361);
  size_t tested_gpu = 0, tested_reference = 0;
  const double worst_gpu = in_front_mm(gpu.fusion, tested_gpu), worst_reference = in_front_mm(reference, tested_reference);
  INFO(tested_reference << " pixels tested; worst in front: reference " << worst_reference << " mm, GPU " << worst_gpu
                        << " mm");
  CHECK(tested_reference > 60);
  CHECK(tested_gpu > 60);
  CHECK(worst_reference < 0.5);
  CHECK(worst_gpu < 0.5);
}

TEST_CASE("ibr_splat: the edge inset is checked", "[ibr_splat]") {
  passes::SplatSettings settings;
  for (float bad : {-0.1f, 0.5f, std::numeric_limits<float>::quiet_NaN()}) {
    settings.edge_inset = bad;
    CHECK_THROWS_WITH(passes::ibr_splat_reference(test::ibr_rig(1, 16, 9, 5, 5, 7, 5).table,
                                                  HostImage(5, 5, PixelFormat::RGBA32F, 0.0f), settings),
                      Catch::Contains("edge_inset"));
  }
}
