// Lumi-Net's whole forward pass: the GPU chain (pipeline::LumiNetBlender) against the chain of
// the passes' C++ references, with random weights, on random warped views of odd sizes, scales 1,
// 2 and 4, 1 to 6 views, several shapes (channels not multiples of 4, no pooled block), to 1e-4
// absolute + 1e-4 relative (errors of 1e-5 per layer through a few layers and the softmax's
// exponential); no view seeing gives an empty portrait; no NaN or Inf. The weights file: a round
// trip, and the refusals name the file.
#include <filesystem>
#include <fstream>
#include <random>

#include "ibr/lumi_net_model.h"
#include "pipeline/lumi_net.h"
#include "support/gpu_test.h"
#include "support/ibr_rig.h"
#include "support/pass_harness.h"

using namespace rt;

namespace {

passes::Portrait run_net(const ibr::LumiNetModel& model, const HostImage& fused, const HostImage& warped,
                         const HostImage& features, uint32_t views) {
  pipeline::LumiNetBlender net(test::gpu(), model, fused.width, fused.height, views);
  test::PassHarness gpu("lumi_net");
  net.add_to(gpu.graph(), gpu.input("fused depth", fused), gpu.input("warped", warped), gpu.input("features", features),
             gpu.output("portrait", fused.width, fused.height, PixelFormat::RGBA32F),
             gpu.output("portrait depth", fused.width, fused.height, PixelFormat::R32F), views);
  const test::PassOutputs out = gpu.run();
  return {out.image("portrait"), out.image("portrait depth")};
}

struct Views {
  HostImage fused, warped, features;
};

Views random_views(std::mt19937& rng, uint32_t width, uint32_t height, uint32_t views, float seen = 0.75f) {
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  Views v{test::random_fused_depth(rng, width, height),
          test::random_image(rng, width, height * views, PixelFormat::RGBA32F),
          test::random_image(rng, width, height * views, PixelFormat::RGBA32F)};
  for (size_t i = 0; i < v.features.texels.size(); i += 4) v.features.texels[i + 3] = unit(rng) < seen ? 1.0f : 0.0f;
  return v;
}

}  // namespace

TEST_CASE("Lumi-Net's GPU forward pass matches the chain of references", "[lumi_net][gpu]") {
  test::NoValidationErrors no_errors;
  std::mt19937 rng(53);
  const ibr::LumiNetShape shapes[] = {{16, 2, 2}, {5, 1, 1}, {7, 0, 4}, {16, 2, 4}};
  const std::pair<uint32_t, uint32_t> sizes[] = {{1, 1}, {9, 1}, {1, 13}, {23, 17}, {61, 35}};
  uint32_t seed = 1;
  for (const ibr::LumiNetShape& shape : shapes)
    for (const auto& [width, height] : sizes)
      for (uint32_t views : {1u, 4u, 6u}) {
        INFO(width << "x" << height << ", " << views << " views, C " << shape.channels << ", " << shape.blocks
                   << " blocks, scale " << shape.scale);
        const ibr::LumiNetModel model = ibr::random_lumi_net(shape, seed++);
        const Views v = random_views(rng, width, height, views);
        const passes::Portrait gpu = run_net(model, v.fused, v.warped, v.features, views);
        const passes::Portrait reference = pipeline::lumi_net_reference(model, v.fused, v.warped, v.features, views);
        RT_REQUIRE_MATCHES(gpu.color, reference.color, 1e-4, 1e-4);
        RT_REQUIRE_MATCHES(gpu.depth, reference.depth, 0.0, 0.0);
      }
}

TEST_CASE("Lumi-Net with no view seeing gives an empty portrait", "[lumi_net][gpu]") {
  test::NoValidationErrors no_errors;
  std::mt19937 rng(59);
  const Views v = random_views(rng, 19, 11, 4, 0.0f);
  const passes::Portrait gpu = run_net(ibr::random_lumi_net({}, 7), v.fused, v.warped, v.features, 4);
  RT_REQUIRE_MATCHES(gpu.color, HostImage(19, 11, PixelFormat::RGBA32F, 0.0f), 0.0, 0.0);
  RT_REQUIRE_MATCHES(gpu.depth, HostImage(19, 11, PixelFormat::R32F, 0.0f), 0.0, 0.0);
}

TEST_CASE("Lumi-Net's weights file", "[lumi_net]") {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "remotetouch-lumi-net-test";
  std::filesystem::create_directories(dir);
  const ibr::LumiNetModel model = ibr::random_lumi_net({5, 1, 4}, 3);
  ibr::save_lumi_net(model, dir / "net.bin");
  const ibr::LumiNetModel loaded = ibr::load_lumi_net(dir / "net.bin");
  REQUIRE(loaded.shape.channels == 5);
  REQUIRE(loaded.shape.blocks == 1);
  REQUIRE(loaded.shape.scale == 4);
  REQUIRE(loaded.parameters == model.parameters);
  std::ofstream(dir / "bad.bin") << "not weights";
  REQUIRE_THROWS_WITH(ibr::load_lumi_net(dir / "bad.bin"), Catch::Contains("bad.bin") && Catch::Contains("RTLUMI01"));
  REQUIRE_THROWS_WITH(ibr::load_lumi_net(dir / "missing.bin"), Catch::Contains("scripts/train-lumi"));
  std::filesystem::resize_file(dir / "net.bin", 100);
  REQUIRE_THROWS_WITH(ibr::load_lumi_net(dir / "net.bin"), Catch::Contains("truncated"));
}
