// The frame graph: ordering from reads and writes, barriers, checks against the shader,
// timings, and deferred destruction.
#include <cstdint>  // the generated SPIR-V headers use uint32_t

#include "copy.comp.h"
#include "hand_alpha.comp.h"
#include "passes/copy.h"
#include "passes/hand_alpha.h"
#include "passes/overlay.h"
#include "passes/person_raster.h"
#include "support/gpu_test.h"
#include "vulkan/frame_graph.h"
#include "vulkan/vk_struct.h"

using namespace rt;

namespace {

struct Images {
  vk::Image a, b, c;
  explicit Images(vk::Context& context, uint32_t w = 13, uint32_t h = 11)
      : a(context, {"image a", w, h, PixelFormat::RGBA32F}),
        b(context, {"image b", w, h, PixelFormat::RGBA32F}),
        c(context, {"image c", w, h, PixelFormat::RGBA32F}) {}
};

}  // namespace

TEST_CASE("a pass runs after the pass that writes what it reads, whatever the order added", "[frame_graph][gpu]") {
  test::NoValidationErrors no_errors;
  vk::Context& context = test::gpu();
  const passes::CopyPass copy(context);
  Images images(context);
  std::mt19937 rng(10);
  const HostImage source = test::random_image(rng, 13, 11, PixelFormat::RGBA32F);
  vk::upload(context, images.a, source);

  vk::FrameGraph graph(context, "test order");
  copy.add_to(graph, images.b, images.c, "second copy");  // reads b, added before b's writer
  copy.add_to(graph, images.a, images.b, "first copy");
  CHECK(graph.execution_order() == std::vector<std::string>{"first copy", "second copy"});
  graph.run();
  RT_REQUIRE_MATCHES(vk::download(context, images.c), source, 0.0, 0.0);

  // The read of b waits for its write: one barrier before the second copy, every frame.
  graph.run();
  const auto barriers = graph.barriers_per_pass();
  REQUIRE(barriers.size() == 2);
  CHECK(barriers[1] >= 1);
}

TEST_CASE("an image copy in the graph runs after its source's writer and before its reader", "[frame_graph][gpu]") {
  test::NoValidationErrors no_errors;
  vk::Context& context = test::gpu();
  const passes::CopyPass copy(context);
  Images images(context);
  std::mt19937 rng(12);
  const HostImage source = test::random_image(rng, 13, 11, PixelFormat::RGBA32F);
  vk::upload(context, images.a, source);
  vk::Image last(context, {"image d", 13, 11, PixelFormat::RGBA32F});
  vk::FrameGraph graph(context, "test image copy");
  copy.add_to(graph, images.c, last, "reader");  // reads the transfer's destination
  graph.add_image_copy("transfer", images.b, images.c);
  copy.add_to(graph, images.a, images.b, "writer");
  // a -> b (kernel), b -> c (transfer), c -> d (kernel), whatever the order added.
  CHECK(graph.execution_order() == std::vector<std::string>{"writer", "transfer", "reader"});
  graph.run();
  RT_REQUIRE_MATCHES(vk::download(context, images.c), source, 0.0, 0.0);
  RT_REQUIRE_MATCHES(vk::download(context, last), source, 0.0, 0.0);

  vk::Image other_size(context, {"image d", 12, 11, PixelFormat::RGBA32F});
  vk::Image other_format(context, {"image e", 13, 11, PixelFormat::R32F});
  REQUIRE_THROWS_WITH(graph.add_image_copy("bad", images.a, other_size), Catch::Contains("differ in size or format"));
  REQUIRE_THROWS_WITH(graph.add_image_copy("bad", images.a, other_format), Catch::Contains("differ in size or format"));
}

TEST_CASE("passes that read each other's outputs are a cycle, reported by name", "[frame_graph][gpu]") {
  test::NoValidationErrors no_errors;
  vk::Context& context = test::gpu();
  const passes::CopyPass copy(context);
  Images images(context);
  vk::FrameGraph graph(context, "test cycle");
  copy.add_to(graph, images.a, images.b, "a to b");
  copy.add_to(graph, images.b, images.a, "b to a");
  CHECK_THROWS_WITH(graph.execution_order(), Catch::Contains("a to b") && Catch::Contains("cycle"));
}

TEST_CASE("bindings are checked against the shader's reflection", "[frame_graph][gpu]") {
  test::NoValidationErrors no_errors;
  vk::Context& context = test::gpu();
  const vk::ComputeKernel copy(context, "copy", copy_comp_spirv);
  const vk::ComputeKernel hand_alpha(context, "hand_alpha", hand_alpha_comp_spirv,
                                    {{"d_min_m", 0.1f}, {"d_max_m", 0.5f}});
  Images images(context);
  vk::Image mask(context, {"mask", 13, 11, PixelFormat::R32F});
  vk::Buffer buffer(context, {"a buffer", 64});
  vk::FrameGraph graph(context, "test bindings");
  auto add_with = [&](const vk::ComputeKernel& kernel, std::vector<vk::Binding> bindings) {
    graph.add_compute_pass({.name = "checked", .kernel = &kernel, .bindings = std::move(bindings), .threads = {13, 11, 1}});
  };
  auto add = [&](std::vector<vk::Binding> bindings) { add_with(copy, std::move(bindings)); };
  CHECK_THROWS_WITH(add({{"source", &images.a}, {"destinaton", &images.b}}),
                    Catch::Contains("no binding 'destinaton'") && Catch::Contains("destination"));
  CHECK_THROWS_WITH(add({{"source", &images.a}}), Catch::Contains("'destination' is not bound"));
  CHECK_THROWS_WITH(add({{"source", &images.a}, {"destination", &mask}}),
                    Catch::Contains("format") && Catch::Contains("mask"));
  CHECK_THROWS_WITH(add({{"source", &images.a}, {"destination", &buffer}}), Catch::Contains("an image in the shader"));
  CHECK_THROWS_WITH(add({{"source", &images.a}, {"source", &images.c}, {"destination", &images.b}}),
                    Catch::Contains("bound twice"));
  CHECK_THROWS_WITH(add_with(hand_alpha, {{"hand_mask", &mask}, {"hand_alpha", &mask}}), Catch::Contains("push constants"));
  CHECK_THROWS_WITH(graph.add_compute_pass({.name = "zero", .kernel = &copy,
                                            .bindings = {{"source", &images.a}, {"destination", &images.b}},
                                            .threads = {0, 1, 1}}),
                    Catch::Contains("thread count of 0"));
  vk::Buffer short_indirect(context, {"short indirect", 8, VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT});
  CHECK_THROWS_WITH(graph.add_compute_pass({.name = "indirect", .kernel = &copy,
                                            .bindings = {{"source", &images.a}, {"destination", &images.b}},
                                            .indirect = &short_indirect}),
                    Catch::Contains("fewer than three uints"));
  CHECK(graph.execution_order().empty());  // nothing half-added
}

TEST_CASE("a push-constant block of the wrong size fails loudly", "[frame_graph][gpu]") {
  test::NoValidationErrors no_errors;
  vk::Context& context = test::gpu();
  const vk::ComputeKernel hand_alpha(context, "hand_alpha", hand_alpha_comp_spirv,
                                    {{"d_min_m", 0.1f}, {"d_max_m", 0.5f}});
  vk::Image mask(context, {"mask", 3, 3, PixelFormat::R32F});
  vk::Image alpha(context, {"alpha", 3, 3, PixelFormat::R32F});
  vk::FrameGraph graph(context, "test push size");
  graph.add_compute_pass({.name = "wrong push", .kernel = &hand_alpha,
                          .bindings = {{"hand_mask", &mask}, {"hand_alpha", &alpha}},
                          .threads = {3, 3, 1},
                          .push_constants = vk::push_constants_from<double>([] { return 0.3; })});
  CHECK_THROWS_WITH(graph.run(), Catch::Contains("pushed 8 bytes") && Catch::Contains("declares 4"));
  context.wait_idle();
}

TEST_CASE("per-pass GPU times are measured for every frame", "[frame_graph][gpu]") {
  test::NoValidationErrors no_errors;
  vk::Context& context = test::gpu();
  const passes::HandAlphaPass hand_alpha(context);
  const passes::OverlayPass overlay(context);
  Images images(context, 64, 48);
  vk::Image mask(context, {"mask", 64, 48, PixelFormat::R32F});
  vk::Image alpha(context, {"alpha", 64, 48, PixelFormat::R32F});
  vk::upload(context, mask, test::filled_image(64, 48, PixelFormat::R32F, 1.0f));
  vk::upload(context, images.a, test::filled_image(64, 48, PixelFormat::RGBA32F, 0.5f));
  vk::upload(context, images.b, test::filled_image(64, 48, PixelFormat::RGBA32F, 0.25f));
  vk::FrameGraph graph(context, "test timing");
  overlay.add_to(graph, images.a, alpha, images.b, images.c);
  hand_alpha.add_to(graph, mask, alpha, [] { return 0.3f; });
  for (int frame = 0; frame < 5; ++frame) graph.run();
  REQUIRE(graph.timing_available());
  const auto timings = graph.timings();
  REQUIRE(timings.size() == 2);
  CHECK(timings[0].name == "hand_alpha");
  CHECK(timings[1].name == "overlay");
  for (const auto& timing : timings) {
    CHECK(timing.frames == 5);
    CHECK(timing.median_ms >= 0.0);
    CHECK(timing.median_ms < 10'000.0);
  }
  // hand_alpha reads a 64x48 r32f mask and writes as much; overlay reads 2 rgba32f + 1 r32f, writes 1 rgba32f.
  CHECK(timings[0].bytes_moved == 2 * 64 * 48 * 4);
  CHECK(timings[1].bytes_moved == (3 * 16 + 4) * 64 * 48);
  CHECK(vk::format_profile(timings).find("overlay") != std::string::npos);
  graph.reset_timings();
  CHECK(graph.timings()[0].frames == 0);

  const auto written = graph.written_images();
  REQUIRE(written.size() == 2);
  CHECK(written[0].first == "hand_alpha");
  CHECK(written[0].second == &alpha);
}

TEST_CASE("a resource released while the GPU still uses it is destroyed later", "[frame_graph][gpu]") {
  test::NoValidationErrors no_errors;
  vk::Context& context = test::gpu();
  uint64_t in_flight = 0;
  {
    vk::Image image(context, {"released early", 512, 512, PixelFormat::RGBA32F});
    vk::CommandBuffer commands(context, "released early commands");
    auto begin = vk::vk_struct<VkCommandBufferBeginInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO);
    vkBeginCommandBuffer(commands.get(), &begin);
    vk::use_image(context, commands.get(), image, vk::access::transfer_write);
    const VkClearColorValue color{{1.0f, 0.0f, 0.0f, 1.0f}};
    const VkImageSubresourceRange range{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    vkCmdClearColorImage(commands.get(), image.image(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &color, 1, &range);
    vkEndCommandBuffer(commands.get());
    in_flight = context.submit(commands.get());
    // image and commands go out of scope here, with the clear possibly still running: the
    // validation layer would report a destroyed in-use object if destruction were immediate.
  }
  context.wait(in_flight);
}

namespace {

// Big copy between two tiny ones: whatever the driver does with timestamps, the big pass must
// take the most time.
void require_big_pass_timed_as_biggest(vk::Context& context) {
  const passes::CopyPass copy(context);
  vk::Image tiny_in(context, {"tiny in", 1, 1}), tiny_out(context, {"tiny out", 1, 1});
  vk::Image tiny_out2(context, {"tiny out 2", 1, 1});
  vk::Image big_in(context, {"big in", 1024, 1024}), big_out(context, {"big out", 1024, 1024});
  vk::FrameGraph graph(context, "test timing attribution");
  copy.add_to(graph, tiny_in, tiny_out, "tiny before");
  copy.add_to(graph, big_in, big_out, "big");
  copy.add_to(graph, tiny_out, tiny_out2, "tiny after");
  for (int frame = 0; frame < 3; ++frame) graph.run();
  const auto timings = graph.timings();
  REQUIRE(timings.size() == 3);
  INFO(vk::format_profile(timings));
  CHECK(timings[1].median_ms > timings[0].median_ms);
  CHECK(timings[1].median_ms > timings[2].median_ms);
}

}  // namespace

TEST_CASE("each pass's time holds its own work, before and after the context has drawn", "[frame_graph][gpu]") {
  test::NoValidationErrors no_errors;
  vk::Context& context = test::gpu();
  require_big_pass_timed_as_biggest(context);
  // llvmpipe defers its timestamps once anything was drawn: draw a triangle, then time again.
  const passes::PersonRasterPass raster(context);
  std::vector<passes::MeshVertex> triangle(3);
  triangle[0].position_part = {-0.1f, -0.1f, 1.0f, 1.0f};
  triangle[1].position_part = {0.1f, -0.1f, 1.0f, 1.0f};
  triangle[2].position_part = {0.0f, 0.1f, 1.0f, 1.0f};
  vk::Buffer mesh(context, {.name = "triangle", .size = sizeof(passes::MeshVertex) * 3,
                            .usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT});
  vk::upload(context, mesh, std::as_bytes(std::span(triangle)));
  vk::Image color(context, {"color", 16, 16, PixelFormat::RGBA8}), depth_m(context, {"depth m", 16, 16, PixelFormat::R32F});
  vk::Image part(context, {"part", 16, 16, PixelFormat::R32F}), depth(context, {"depth buffer", 16, 16, PixelFormat::D32F});
  Camera camera;
  camera.intrinsics = {16, 16, 16, 16, 7.5, 7.5, {}};
  vk::FrameGraph draw(context, "test draw");
  raster.add_to(draw, mesh, [] { return 3u; }, [&] { return passes::raster_view(camera, 0.1, 10.0); },
                {&color, &depth_m, &part, &depth});
  draw.run();
  require_big_pass_timed_as_biggest(context);
}
