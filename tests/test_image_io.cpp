// PNG (8 and 16 bits) and EXR through OpenCV: round trips within the format's precision.
#include <catch2/catch.hpp>

#include <filesystem>
#include <limits>
#include <random>

#include "image/image_crop.h"
#include "image/image_io.h"
#include "support/gpu_test.h"

using namespace rt;

namespace {

std::filesystem::path scratch(const std::string& name) {
  const auto folder = std::filesystem::temp_directory_path() / ("remotetouch-test-image-io-" + std::to_string(getpid()));
  std::filesystem::create_directories(folder);
  return folder / name;
}

}  // namespace

TEST_CASE("EXR keeps float values exactly, one and four channels", "[image_io]") {
  std::mt19937 rng(12);
  for (PixelFormat format : {PixelFormat::R32F, PixelFormat::RGBA32F}) {
    const HostImage image = test::random_image(rng, 7, 5, format, -3.0f, 40.0f);
    write_image(scratch("values.exr"), image);
    RT_REQUIRE_MATCHES(read_image(scratch("values.exr")), image, 0.0, 0.0);
  }
}

TEST_CASE("PNG keeps values to 8 or 16 bits and clamps the rest", "[image_io]") {
  std::mt19937 rng(13);
  HostImage image = test::random_image(rng, 33, 17, PixelFormat::RGBA32F);
  write_image(scratch("eight.png"), image, PngDepth::Eight);
  RT_REQUIRE_MATCHES(read_image(scratch("eight.png")), image, 0.5 / 255 + 1e-6, 0.0);
  write_image(scratch("sixteen.png"), image, PngDepth::Sixteen);
  RT_REQUIRE_MATCHES(read_image(scratch("sixteen.png")), image, 0.5 / 65535 + 1e-7, 0.0);

  image.texels[0] = std::numeric_limits<float>::quiet_NaN();
  image.texels[1] = 7.0f;
  image.texels[2] = -1.0f;
  write_image(scratch("clamped.png"), image);
  const HostImage read = read_image(scratch("clamped.png"));
  CHECK(read.texels[0] == 0.0f);
  CHECK(read.texels[1] == 1.0f);
  CHECK(read.texels[2] == 0.0f);
}

TEST_CASE("16-bit depth in millimetres round-trips exactly", "[image_io]") {
  HostImage depth(33, 17, PixelFormat::R16U);
  for (size_t i = 0; i < depth.texels.size(); ++i) depth.texels[i] = float((i * 977) % 65536);
  write_image(scratch("depth.png"), depth);
  RT_REQUIRE_MATCHES(read_depth_png(scratch("depth.png")), depth, 0.0, 0.0);
  write_image(scratch("color.png"), HostImage(3, 3, PixelFormat::RGBA8, 0.5f));
  CHECK_THROWS_WITH(read_depth_png(scratch("color.png")), Catch::Contains("not a one-channel 16-bit PNG"));
  CHECK_THROWS_WITH(write_image(scratch("depth.exr"), depth), Catch::Contains(".png"));
}

TEST_CASE("bad paths and extensions say what is wrong", "[image_io]") {
  const HostImage image(2, 2, PixelFormat::R32F);
  CHECK_THROWS_WITH(write_image(scratch("picture.bmp2"), image), Catch::Contains(".png or .exr"));
  CHECK_THROWS_WITH(read_image(scratch("does-not-exist.png")), Catch::Contains("does-not-exist.png"));
}

TEST_CASE("crop to the covered box and paste back on zero", "[image_io]") {
  HostImage mask(13, 7, PixelFormat::R32F);
  HostImage color(13, 7, PixelFormat::RGBA32F);
  for (size_t i = 0; i < color.texels.size(); ++i) color.texels[i] = float(i % 97) / 97.0f;
  CHECK(nonzero_box(mask).empty());
  mask.at(0, 0) = std::numeric_limits<float>::quiet_NaN();  // NaN is nothing
  mask.at(3, 2) = 0.5f;
  mask.at(9, 5) = 1.0f;
  const PixelBox box = nonzero_box(mask);
  CHECK(box.x == 3);
  CHECK(box.y == 2);
  CHECK(box.width == 7);
  CHECK(box.height == 4);
  const HostImage part = crop(color, box);
  const HostImage back = paste_on_zero(part, box.x, box.y, 13, 7);
  for (uint32_t y = 0; y < 7; ++y)
    for (uint32_t x = 0; x < 13; ++x)
      for (uint32_t c = 0; c < 4; ++c) {
        const bool inside = x >= 3 && x < 10 && y >= 2 && y < 6;
        REQUIRE(back.at(x, y, c) == (inside ? color.at(x, y, c) : 0.0f));
      }
  CHECK_THROWS_WITH(crop(color, {10, 0, 4, 1}), Catch::Contains("outside"));
  CHECK_THROWS_WITH(paste_on_zero(part, 7, 0, 13, 7), Catch::Contains("does not fit"));
}
