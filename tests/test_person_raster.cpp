// person_raster pass: the GPU rasterizer against the C++ reference rasterizer on random
// triangle soups of odd sizes and on the hard cases (behind the camera, across the near plane,
// degenerate triangles). Tolerances: away from triangle edges the part mask is exact, color
// within one 8-bit step plus float shading differences (2/255), linear depth within 1e-5
// relative; within one pixel of an edge the GPU's tie-breaking rule may differ. The face texture
// (head vertices, negative stripe period) is compared the same way: it is float and bilinear on
// both sides, so it adds no more than rounding.
#include <cmath>
#include <random>
#include <sstream>

#include "passes/person_raster.h"
#include "support/gpu_test.h"
#include "support/pass_harness.h"

using namespace rt;
using passes::MeshVertex;

namespace {

Camera test_camera_person_raster(uint32_t width, uint32_t height) {
  Camera camera;
  camera.name = "test";
  camera.intrinsics = {width, height, 0.8 * width, 0.8 * width, 0.5 * width - 0.5 + 0.3, 0.5 * height - 0.5 - 0.2, {}};
  return camera;  // at the origin, looking along +z (OpenCV: y down)
}

MeshVertex vertex(const Eigen::Vector3d& p, float part, const Eigen::Vector3f& color, const Eigen::Vector3d& normal,
                  float stripe_period = 0.0f) {
  MeshVertex v{};
  v.position_part = {float(p.x()), float(p.y()), float(p.z()), part};
  v.normal_stripe = {float(normal.x()), float(normal.y()), float(normal.z()), stripe_period};
  v.color = {color.x(), color.y(), color.z(), 1.0f};
  v.stripe_color = {0.1f, 0.2f, 0.7f, 1.0f};
  return v;
}

std::vector<MeshVertex> random_soup(std::mt19937& rng, int triangles, double z_low, double z_high) {
  std::uniform_real_distribution<double> xy(-1.0, 1.0), z(z_low, z_high), unit(0.0, 1.0), offset(-0.3, 0.3),
      spread(-0.9, 0.9);
  std::vector<MeshVertex> mesh;
  for (int t = 0; t < triangles; ++t) {
    const Eigen::Vector3d centre(xy(rng), xy(rng), z(rng));
    const Eigen::Vector3f color(float(unit(rng)), float(unit(rng)), float(unit(rng)));
    const float part = t % 2 ? 2.0f : 1.0f;
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d normal(offset(rng), offset(rng), 1.0);
      mesh.push_back(vertex(centre + Eigen::Vector3d(spread(rng), spread(rng), offset(rng)), part, color, normal));
    }
  }
  return mesh;
}

struct GpuRasterPersonRaster {
  HostImage color, depth_m, part;
};

GpuRasterPersonRaster run_gpu_person_raster(const std::vector<MeshVertex>& mesh, const Camera& camera, const HostImage* face = nullptr) {
  const passes::PersonRasterPass pass(test::gpu());
  test::PassHarness gpu("person_raster");
  const uint32_t w = camera.intrinsics.width, h = camera.intrinsics.height;
  const auto view = passes::raster_view(camera, 0.1, 10.0);
  vk::Image* face_texture = face ? &gpu.input("face texture", *face) : nullptr;
  pass.add_to(gpu.graph(), gpu.input_buffer("test mesh", mesh), [&] { return uint32_t(mesh.size()); }, [view] { return view; },
              {&gpu.output("color", w, h, PixelFormat::RGBA8), &gpu.output("depth m", w, h, PixelFormat::R32F),
               &gpu.output("part", w, h, PixelFormat::R32F), &gpu.scratch("depth buffer", w, h, PixelFormat::D32F)},
              "person_raster", face_texture);
  const test::PassOutputs out = gpu.run();
  return {out.image("color"), out.image("depth m"), out.image("part")};
}

// Compares away from edges; returns how many covered pixels were compared.
size_t require_matches_person_raster(const GpuRasterPersonRaster& gpu, const passes::RasterReference& reference) {
  REQUIRE(test::count_non_finite(gpu.color) == 0);
  REQUIRE(test::count_non_finite(gpu.depth_m) == 0);
  REQUIRE(test::count_non_finite(gpu.part) == 0);
  size_t compared = 0, mismatches = 0;
  std::string first;
  for (uint32_t y = 0; y < reference.part.height; ++y)
    for (uint32_t x = 0; x < reference.part.width; ++x) {
      if (reference.near_edge.at(x, y) != 0.0f) continue;
      bool same = gpu.part.at(x, y) == reference.part.at(x, y);
      for (uint32_t c = 0; c < 4; ++c) same &= std::abs(gpu.color.at(x, y, c) - reference.color.at(x, y, c)) <= 2.0f / 255.0f + 1e-6f;
      const float want = reference.depth_m.at(x, y);
      same &= std::abs(gpu.depth_m.at(x, y) - want) <= 1e-5f * std::abs(want) + 1e-6f;
      compared += reference.part.at(x, y) != 0.0f;
      if (!same && mismatches++ == 0) {
        std::ostringstream where;  // (a string + chain trips GCC 12's -Wrestrict false positive)
        where << "(" << x << ", " << y << "): gpu part " << gpu.part.at(x, y) << " depth " << gpu.depth_m.at(x, y)
              << " color " << gpu.color.at(x, y, 0) << ", reference part " << reference.part.at(x, y) << " depth " << want
              << " color " << reference.color.at(x, y, 0);
        first = where.str();
      }
    }
  INFO("first mismatch " << first);
  REQUIRE(mismatches == 0);
  return compared;
}

}  // namespace

TEST_CASE("person_raster: random triangle soups of odd sizes", "[person_raster][gpu]") {
  test::NoValidationErrors no_errors;
  std::mt19937 rng(21);
  for (const auto& [width, height] : std::vector<std::pair<uint32_t, uint32_t>>{{97, 61}, {64, 64}, {33, 17}, {160, 91}}) {
    INFO(width << "x" << height);
    const Camera camera = test_camera_person_raster(width, height);
    const auto mesh = random_soup(rng, 12, 1.2, 3.0);
    const auto view = passes::raster_view(camera, 0.1, 10.0);
    const size_t compared = require_matches_person_raster(run_gpu_person_raster(mesh, camera), passes::person_raster_reference(mesh, view, width, height));
    CHECK(compared > size_t(width * height / 20));  // the comparison is not vacuous
  }
}

TEST_CASE("person_raster: the face texture on head vertices", "[person_raster][gpu]") {
  test::NoValidationErrors no_errors;
  std::mt19937 rng(23);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f), uv(-0.3f, 1.3f), facing(-0.5f, 1.5f);
  // An odd-sized texture: the photo's color relative to the skin (0.3 to 1.8) and its alpha.
  HostImage face(13, 9, PixelFormat::RGBA32F);
  for (float& texel : face.texels) texel = unit(rng);
  for (uint32_t y = 0; y < face.height; ++y)
    for (uint32_t x = 0; x < face.width; ++x)
      for (uint32_t c = 0; c < 3; ++c) face.at(x, y, c) = 0.3f + 1.5f * face.at(x, y, c);
  for (const auto& [width, height] : std::vector<std::pair<uint32_t, uint32_t>>{{97, 61}, {33, 17}}) {
    INFO(width << "x" << height);
    const Camera camera = test_camera_person_raster(width, height);
    auto mesh = random_soup(rng, 12, 1.2, 3.0);
    // Every other triangle is head: texture coordinates beyond [0, 1] too (clamped to the edge),
    // and facing beyond [0, 1] (clamped).
    for (size_t i = 0; i < mesh.size(); ++i)
      if ((i / 3) % 2 == 0) {
        mesh[i].normal_stripe[3] = -1.0f;
        mesh[i].stripe_color = {uv(rng), uv(rng), facing(rng), 1.0f};
      }
    const auto view = passes::raster_view(camera, 0.1, 10.0);
    const size_t compared =
        require_matches_person_raster(run_gpu_person_raster(mesh, camera, &face), passes::person_raster_reference(mesh, view, width, height, &face));
    CHECK(compared > size_t(width * height / 20));
    // Without a texture the head is its plain albedo, on both sides.
    const auto plain = passes::person_raster_reference(mesh, view, width, height);
    require_matches_person_raster(run_gpu_person_raster(mesh, camera), plain);
    size_t differs = 0;
    const auto textured = passes::person_raster_reference(mesh, view, width, height, &face);
    for (size_t i = 0; i < plain.color.texels.size(); ++i) differs += std::abs(plain.color.texels[i] - textured.color.texels[i]) > 0.02f;
    CHECK(differs > 10);  // the texture shows
  }
}

TEST_CASE("person_raster: behind the camera, across the near plane, degenerate", "[person_raster][gpu]") {
  test::NoValidationErrors no_errors;
  std::mt19937 rng(22);
  const Camera camera = test_camera_person_raster(97, 61);
  const auto view = passes::raster_view(camera, 0.1, 10.0);
  const Eigen::Vector3f grey(0.5f, 0.5f, 0.5f);
  const Eigen::Vector3d facing(0, 0, -1);

  SECTION("everything behind the camera draws nothing") {
    const auto mesh = random_soup(rng, 20, -3.0, -0.5);
    const GpuRasterPersonRaster gpu = run_gpu_person_raster(mesh, camera);
    CHECK(*std::max_element(gpu.part.texels.begin(), gpu.part.texels.end()) == 0.0f);
    require_matches_person_raster(gpu, passes::person_raster_reference(mesh, view, 97, 61));
  }
  SECTION("triangles across the near plane are clipped") {
    const std::vector<MeshVertex> mesh = {vertex({-1, -1, -0.5}, 1, grey, facing), vertex({1, -1, 2.0}, 1, grey, facing),
                                          vertex({0, 1, 2.0}, 1, grey, facing)};
    const size_t compared = require_matches_person_raster(run_gpu_person_raster(mesh, camera), passes::person_raster_reference(mesh, view, 97, 61));
    CHECK(compared > 100);
  }
  SECTION("degenerate triangles (repeated or collinear vertices) draw nothing") {
    const std::vector<MeshVertex> mesh = {vertex({0, 0, 1}, 1, grey, facing), vertex({0, 0, 1}, 1, grey, facing),
                                          vertex({0.5, 0.1, 1}, 1, grey, facing), vertex({0, 0, 1}, 2, grey, facing),
                                          vertex({0.2, 0.2, 1}, 2, grey, {0, 0, 0}), vertex({0.4, 0.4, 1}, 2, grey, facing)};
    const GpuRasterPersonRaster gpu = run_gpu_person_raster(mesh, camera);
    CHECK(*std::max_element(gpu.part.texels.begin(), gpu.part.texels.end()) == 0.0f);
  }
  SECTION("an empty mesh draws nothing") {
    const GpuRasterPersonRaster gpu = run_gpu_person_raster({}, camera);
    CHECK(*std::max_element(gpu.depth_m.texels.begin(), gpu.depth_m.texels.end()) == 0.0f);
  }
  SECTION("a zero normal is lit, not NaN") {
    const std::vector<MeshVertex> mesh = {vertex({-1, -1, 2}, 1, grey, {0, 0, 0}), vertex({1, -1, 2}, 1, grey, {0, 0, 0}),
                                          vertex({0, 1, 2}, 1, grey, {0, 0, 0})};
    require_matches_person_raster(run_gpu_person_raster(mesh, camera), passes::person_raster_reference(mesh, view, 97, 61));
  }
}

TEST_CASE("person_raster: nearer surfaces win, and stripes show", "[person_raster][gpu]") {
  test::NoValidationErrors no_errors;
  const Camera camera = test_camera_person_raster(64, 64);
  const Eigen::Vector3d facing(0, 0, -1);
  // A striped quad at 2 m behind a hand-part triangle at 1 m.
  std::vector<MeshVertex> mesh;
  const Eigen::Vector3f white(0.9f, 0.9f, 0.9f);
  for (const auto& p : {Eigen::Vector3d(-2, -2, 2), Eigen::Vector3d(2, -2, 2), Eigen::Vector3d(2, 2, 2),
                        Eigen::Vector3d(-2, -2, 2), Eigen::Vector3d(2, 2, 2), Eigen::Vector3d(-2, 2, 2)})
    mesh.push_back(vertex(p, 1, white, facing, 0.2f));
  for (const auto& p : {Eigen::Vector3d(-0.2, -0.2, 1), Eigen::Vector3d(0.2, -0.2, 1), Eigen::Vector3d(0, 0.2, 1)})
    mesh.push_back(vertex(p, 2, {0.8f, 0.6f, 0.5f}, facing));
  const GpuRasterPersonRaster gpu = run_gpu_person_raster(mesh, camera);
  CHECK(gpu.part.at(32, 32) == 2.0f);
  CHECK(gpu.depth_m.at(32, 32) == Approx(1.0f).epsilon(1e-5));
  CHECK(gpu.part.at(2, 2) == 1.0f);
  CHECK(gpu.depth_m.at(2, 2) == Approx(2.0f).epsilon(1e-5));
  // Both stripe colors appear on the quad; the reference agrees on all but stripe borders.
  const auto reference = passes::person_raster_reference(mesh, passes::raster_view(camera, 0.1, 10.0), 64, 64);
  size_t blue = 0, same = 0, total = 0;
  for (uint32_t y = 0; y < 64; ++y)
    for (uint32_t x = 0; x < 64; ++x) {
      if (gpu.part.at(x, y) != 1.0f || reference.near_edge.at(x, y) != 0.0f) continue;
      ++total;
      blue += gpu.color.at(x, y, 2) > gpu.color.at(x, y, 0) + 0.2f;
      same += std::abs(gpu.color.at(x, y, 0) - reference.color.at(x, y, 0)) <= 2.0f / 255.0f;
    }
  CHECK(blue > total / 4);
  CHECK(blue < 3 * total / 4);
  CHECK(same >= total * 95 / 100);  // at most the rows on a stripe border differ
}
