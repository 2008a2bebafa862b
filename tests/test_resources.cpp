// Images and buffers: upload and readback round trips, names, and clear errors.
#include <cstring>

#include "support/gpu_test.h"
#include "vulkan/resources.h"

using namespace rt;

TEST_CASE("images round-trip through upload and readback in every format", "[resources][gpu]") {
  test::NoValidationErrors no_errors;
  vk::Context& context = test::gpu();
  std::mt19937 rng(11);
  for (PixelFormat format : {PixelFormat::R32F, PixelFormat::RGBA32F, PixelFormat::RGBA8}) {
    for (const auto& [width, height] : test::odd_sizes()) {
      INFO(format_name(format) << " " << width << "x" << height);
      HostImage pixels = test::random_image(rng, width, height, format);
      if (format == PixelFormat::RGBA8)
        for (float& v : pixels.texels) v = std::round(v * 255.0f) / 255.0f;
      vk::Image image(context, {"round trip", width, height, format});
      vk::upload(context, image, pixels);
      RT_REQUIRE_MATCHES(vk::download(context, image), pixels, 0.0, 0.0);
    }
  }
}

TEST_CASE("buffers round-trip", "[resources][gpu]") {
  test::NoValidationErrors no_errors;
  vk::Context& context = test::gpu();
  vk::Buffer buffer(context, {"round trip buffer", 1001});
  std::vector<std::byte> bytes(1001);
  for (size_t i = 0; i < bytes.size(); ++i) bytes[i] = std::byte(i * 7 + 3);
  vk::upload(context, buffer, bytes);
  CHECK(vk::download(context, buffer) == bytes);
  CHECK_THROWS_WITH(vk::upload(context, buffer, std::vector<std::byte>(2000)), Catch::Contains("round trip buffer"));
}

TEST_CASE("bad sizes and mismatched uploads say what is wrong", "[resources][gpu]") {
  test::NoValidationErrors no_errors;
  vk::Context& context = test::gpu();
  CHECK_THROWS_WITH(vk::Image(context, {"empty", 0, 4, PixelFormat::R32F}), Catch::Contains("'empty'") && Catch::Contains("at least 1"));
  CHECK_THROWS_WITH(vk::Image(context, {"huge", 1u << 20, 4, PixelFormat::R32F}), Catch::Contains("larger than"));
  CHECK_THROWS_WITH(vk::Buffer(context, {"nothing", 0}), Catch::Contains("'nothing'"));
  vk::Image image(context, {"target", 4, 4, PixelFormat::RGBA32F});
  CHECK_THROWS_WITH(vk::upload(context, image, HostImage(4, 4, PixelFormat::R32F)),
                    Catch::Contains("'target'") && Catch::Contains("r32f"));
  HostImage short_image(4, 4, PixelFormat::RGBA32F);
  short_image.texels.resize(3);
  CHECK_THROWS_WITH(vk::upload(context, image, short_image), Catch::Contains("holds 3 values"));
}

TEST_CASE("samplers are created and named", "[resources][gpu]") {
  test::NoValidationErrors no_errors;
  vk::Context& context = test::gpu();
  const vk::Sampler linear(context, "bilinear clamp");
  const vk::Sampler nearest(context, "nearest clamp", VK_FILTER_NEAREST);
  CHECK(linear.get() != VK_NULL_HANDLE);
  CHECK(nearest.get() != linear.get());
}

TEST_CASE("handles move and release once", "[resources][gpu]") {
  test::NoValidationErrors no_errors;
  vk::Context& context = test::gpu();
  vk::Image first(context, {"moved", 3, 3, PixelFormat::R32F});
  const VkImage raw = first.image();
  vk::Image second = std::move(first);
  CHECK(second.image() == raw);
  std::vector<vk::Image> many;
  for (int i = 0; i < 10; ++i) many.emplace_back(context, vk::ImageDesc{"many", 2, 2, PixelFormat::R32F});
  many.clear();
  context.wait_idle();
}
