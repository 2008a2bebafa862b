// lumi_softmax: GPU against the C++ reference on random logits of odd sizes with random coverage,
// 1 to 6 views, to 1e-6 absolute + 1e-5 relative (exp() differs in its last bits); by hand: the
// softmax over seeing views only, one view, no view (alpha 0, weights 0), NaN, -Inf and +Inf
// weight logits, NaN and infinite alpha logits, every seeing view's logit out. Weights sum to 1
// wherever a view sees. No NaN or Inf anywhere.
#include <cmath>
#include <limits>
#include <random>

#include "passes/lumi_softmax.h"
#include "support/lumi_tensors.h"

using namespace rt;

namespace {

constexpr float kNaNLumiSoftmax = std::numeric_limits<float>::quiet_NaN();
constexpr float kInfLumiSoftmax = std::numeric_limits<float>::infinity();

passes::LumiTensor run_softmax(const passes::LumiTensor& logits, const passes::LumiTensor& coverage) {
  const passes::LumiSoftmaxPass pass(test::gpu());
  test::PassHarness gpu("lumi_softmax");
  pass.add_to(gpu.graph(), test::input_tensor(gpu, "logits", logits), test::input_tensor(gpu, "coverage", coverage),
              test::output_tensor(gpu, "blending", 1, 1 + logits.views, logits.width, logits.height), logits.width,
              logits.height, logits.views);
  return test::tensor_of(gpu.run(), "blending", 1, 1 + logits.views, logits.width, logits.height);
}

}  // namespace

TEST_CASE("lumi_softmax on random logits, odd sizes", "[lumi_softmax][gpu]") {
  test::NoValidationErrors no_errors;
  std::mt19937 rng(29);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (const auto& [width, height] : test::lumi_sizes())
    for (uint32_t views : {1u, 3u, 6u}) {
      INFO(width << "x" << height << ", " << views << " views");
      const passes::LumiTensor logits = passes::random_lumi_tensor(rng, views, 2, width, height, -20.0f, 20.0f);
      passes::LumiTensor coverage = passes::random_lumi_tensor(rng, views, 1, width, height, 0.0f, 1.0f);
      for (float& c : coverage.values)
        if (unit(rng) < 0.4f) c = 0.0f;
      const passes::LumiTensor gpu = run_softmax(logits, coverage);
      RT_REQUIRE_MATCHES(test::as_image(gpu), test::as_image(passes::lumi_softmax_reference(logits, coverage)), 1e-6, 1e-5);
      for (uint32_t y = 0; y < height; ++y)
        for (uint32_t x = 0; x < width; ++x) {
          bool any = false;
          float sum = 0.0f;
          for (uint32_t v = 0; v < views; ++v) any |= coverage.at(v, 0, x, y) > 0.0f, sum += gpu.at(0, 1 + v, x, y);
          REQUIRE(sum == Approx(any ? 1.0f : 0.0f).margin(1e-5));
        }
    }
}

TEST_CASE("lumi_softmax hard cases", "[lumi_softmax][gpu]") {
  test::NoValidationErrors no_errors;
  // Three views, one pixel per case: set the weight and alpha logits and which views see.
  struct Case {
    float weight[3], alpha[3], coverage[3];
  };
  auto run = [](const Case& c) {
    passes::LumiTensor logits(3, 2, 1, 1), coverage(3, 1, 1, 1);
    for (uint32_t v = 0; v < 3; ++v) {
      logits.at(v, 0, 0, 0) = c.weight[v];
      logits.at(v, 1, 0, 0) = c.alpha[v];
      coverage.at(v, 0, 0, 0) = c.coverage[v];
    }
    const passes::LumiTensor gpu = run_softmax(logits, coverage);
    RT_REQUIRE_MATCHES(test::as_image(gpu), test::as_image(passes::lumi_softmax_reference(logits, coverage)), 1e-6, 1e-5);
    return gpu;
  };
  SECTION("only the seeing views share, by their logits; alpha from their mean alpha logit") {
    const passes::LumiTensor gpu = run({{0.0f, std::log(3.0f), 50.0f}, {1.0f, -1.0f, 100.0f}, {1, 0.25f, 0}});
    REQUIRE(gpu.at(0, 1, 0, 0) == Approx(0.25f).epsilon(1e-5));
    REQUIRE(gpu.at(0, 2, 0, 0) == Approx(0.75f).epsilon(1e-5));
    REQUIRE(gpu.at(0, 3, 0, 0) == 0.0f);
    REQUIRE(gpu.at(0, 0, 0, 0) == Approx(0.5f).epsilon(1e-6));
  }
  SECTION("one seeing view takes all the weight") {
    const passes::LumiTensor gpu = run({{-30.0f, 5.0f, 5.0f}, {2.0f, 0.0f, 0.0f}, {1, 0, 0}});
    REQUIRE(gpu.at(0, 1, 0, 0) == 1.0f);
    REQUIRE(gpu.at(0, 0, 0, 0) == Approx(1.0f / (1.0f + std::exp(-2.0f))).epsilon(1e-5));
  }
  SECTION("no view sees: alpha 0 and weights 0, whatever the logits") {
    const passes::LumiTensor gpu = run({{kNaNLumiSoftmax, kInfLumiSoftmax, 3.0f}, {kInfLumiSoftmax, kNaNLumiSoftmax, 1.0f}, {0, 0, 0}});
    for (uint32_t p = 0; p < 4; ++p) REQUIRE(gpu.at(0, p, 0, 0) == 0.0f);
  }
  SECTION("NaN and -Inf weight logits leave the softmax") {
    const passes::LumiTensor gpu = run({{kNaNLumiSoftmax, -kInfLumiSoftmax, 1.0f}, {0.0f, 0.0f, 0.0f}, {1, 1, 1}});
    REQUIRE(gpu.at(0, 1, 0, 0) == 0.0f);
    REQUIRE(gpu.at(0, 2, 0, 0) == 0.0f);
    REQUIRE(gpu.at(0, 3, 0, 0) == 1.0f);
  }
  SECTION("+Inf weight logits share the weight") {
    const passes::LumiTensor gpu = run({{kInfLumiSoftmax, kInfLumiSoftmax, 1e3f}, {0.0f, 0.0f, 0.0f}, {1, 1, 1}});
    REQUIRE(gpu.at(0, 1, 0, 0) == 0.5f);
    REQUIRE(gpu.at(0, 2, 0, 0) == 0.5f);
    REQUIRE(gpu.at(0, 3, 0, 0) == 0.0f);
  }
  SECTION("every seeing view's logit NaN or -Inf: they share equally") {
    const passes::LumiTensor gpu = run({{kNaNLumiSoftmax, -kInfLumiSoftmax, 7.0f}, {0.0f, 0.0f, 0.0f}, {1, 1, 0}});
    REQUIRE(gpu.at(0, 1, 0, 0) == 0.5f);
    REQUIRE(gpu.at(0, 2, 0, 0) == 0.5f);
    REQUIRE(gpu.at(0, 3, 0, 0) == 0.0f);
  }
  SECTION("alpha logits: NaN ones are skipped, all NaN gives 0, +Inf gives 1, +Inf with -Inf gives 0") {
    REQUIRE(run({{0, 0, 0}, {kNaNLumiSoftmax, 0.0f, 0.0f}, {1, 1, 0}}).at(0, 0, 0, 0) == Approx(0.5f).epsilon(1e-6));
    REQUIRE(run({{0, 0, 0}, {kNaNLumiSoftmax, kNaNLumiSoftmax, 0.0f}, {1, 1, 0}}).at(0, 0, 0, 0) == 0.0f);
    REQUIRE(run({{0, 0, 0}, {kInfLumiSoftmax, 0.0f, 0.0f}, {1, 1, 0}}).at(0, 0, 0, 0) == 1.0f);
    REQUIRE(run({{0, 0, 0}, {kInfLumiSoftmax, -kInfLumiSoftmax, 0.0f}, {1, 1, 0}}).at(0, 0, 0, 0) == 0.0f);
    REQUIRE(run({{0, 0, 0}, {-kInfLumiSoftmax, -kInfLumiSoftmax, 0.0f}, {1, 1, 0}}).at(0, 0, 0, 0) == 0.0f);
  }
}
