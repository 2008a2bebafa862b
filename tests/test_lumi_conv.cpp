// lumi_conv: GPU against the C++ reference on random tensors of odd sizes (1x1, a row, a column,
// sizes off the 8x8 tile), 3x3 and 1x1, with and without ReLU, channel counts that are not
// multiples of 4, counts past the shader's 16-channel chunk (17: a first and a last chunk; 48 and
// 120: chunks in between too, 120 more than one uniform buffer of the whole layer would hold) and
// past its 16-output group (20, 33: two and three dispatches), 1 to 6 views, a layer at an offset in a larger parameter
// buffer. Tolerance 1e-5 absolute + 1e-5 relative: the shader sums in the reference's order, only
// fused multiply-adds differ. By hand: the zero padding at the
// borders and a 1x1 layer's plain matrix product. No NaN or Inf.
#include <random>

#include "passes/lumi_conv.h"
#include "support/lumi_tensors.h"

using namespace rt;

namespace {

passes::LumiTensor run_conv(const passes::LumiTensor& source, const std::vector<float>& parameters, size_t offset,
                            const passes::LumiConvShape& shape) {
  const passes::LumiConvPass pass(test::gpu(), shape);
  test::PassHarness gpu("lumi_conv");
  passes::LumiConvWeights weights = pass.upload_weights(test::gpu(), parameters, offset, "weights");
  pass.add_to(gpu.graph(), "lumi_conv", test::input_tensor(gpu, "source", source), weights,
              test::output_tensor(gpu, "result", source.views, shape.out_channels, source.width, source.height),
              source.width, source.height, source.views);
  return test::tensor_of(gpu.run(), "result", source.views, shape.out_channels, source.width, source.height);
}

std::vector<float> random_parameters(std::mt19937& rng, size_t count) {
  std::uniform_real_distribution<float> value(-0.5f, 0.5f);
  std::vector<float> p(count);
  for (float& v : p) v = value(rng);
  return p;
}

}  // namespace

TEST_CASE("lumi_conv on random tensors, odd sizes and channel counts", "[lumi_conv][gpu]") {
  test::NoValidationErrors no_errors;
  std::mt19937 rng(71);
  const passes::LumiConvShape shapes[] = {
      {7, 16, 3, true}, {48, 16, 3, true}, {17, 5, 3, false}, {3, 1, 3, true}, {16, 2, 1, false}, {5, 7, 1, true},
      {5, 20, 3, true}, {6, 33, 1, false}, {120, 3, 3, true}};
  for (const auto& [width, height] : test::lumi_sizes())
    for (const passes::LumiConvShape& shape : shapes)
      for (uint32_t views : {1u, 4u}) {
        if (shape.in_channels >= 48 && width * height > 600) continue;  // the slowest shapes on small sizes only
        INFO(width << "x" << height << ", " << views << " views, " << shape.in_channels << " -> " << shape.out_channels
                   << ", " << shape.kernel_size << "x" << shape.kernel_size << (shape.relu ? " ReLU" : ""));
        const passes::LumiTensor source = passes::random_lumi_tensor(rng, views, shape.in_channels, width, height);
        const size_t offset = 13;  // a layer after others in the network's one buffer
        const std::vector<float> parameters = random_parameters(rng, offset + shape.parameter_count() + 3);
        const passes::LumiTensor gpu = run_conv(source, parameters, offset, shape);
        const passes::LumiTensor reference = passes::lumi_conv_reference(source, parameters, offset, shape);
        RT_REQUIRE_MATCHES(test::as_image(gpu), test::as_image(reference), 1e-5, 1e-5);
      }
}

TEST_CASE("lumi_conv by hand: zero padding, bias, 1x1 as a matrix product, six views", "[lumi_conv][gpu]") {
  test::NoValidationErrors no_errors;
  SECTION("a 3x3 of ones over a 3x2 of ones counts the neighbours inside, plus the bias") {
    const passes::LumiConvShape shape{1, 1, 3, false};
    std::vector<float> parameters(shape.parameter_count(), 1.0f);
    parameters.back() = 0.5f;  // bias
    const passes::LumiTensor gpu = run_conv(passes::LumiTensor(1, 1, 3, 2, 1.0f), parameters, 0, shape);
    // Corners see 4 inputs, the middle column 6.
    REQUIRE(gpu.at(0, 0, 0, 0) == 4.5f);
    REQUIRE(gpu.at(0, 0, 1, 0) == 6.5f);
    REQUIRE(gpu.at(0, 0, 2, 1) == 4.5f);
  }
  SECTION("1x1: out = W in + b per pixel, ReLU clamps the negative") {
    const passes::LumiConvShape shape{2, 2, 1, true};
    const std::vector<float> parameters = {1.0f, 2.0f, -3.0f, 0.0f, 0.25f, 0.0f};  // W (2x2), b
    passes::LumiTensor source(1, 2, 1, 1);
    source.at(0, 0, 0, 0) = 1.0f;
    source.at(0, 1, 0, 0) = 2.0f;
    const passes::LumiTensor gpu = run_conv(source, parameters, 0, shape);
    REQUIRE(gpu.at(0, 0, 0, 0) == 5.25f);
    REQUIRE(gpu.at(0, 1, 0, 0) == 0.0f);
  }
  SECTION("views are a batch: each view's result is its own") {
    std::mt19937 rng(5);
    const passes::LumiConvShape shape{7, 16, 3, true};
    const passes::LumiTensor source = passes::random_lumi_tensor(rng, 6, 7, 11, 9);
    const std::vector<float> parameters = random_parameters(rng, shape.parameter_count());
    RT_REQUIRE_MATCHES(test::as_image(run_conv(source, parameters, 0, shape)),
                       test::as_image(passes::lumi_conv_reference(source, parameters, 0, shape)), 1e-5, 1e-5);
  }
}

TEST_CASE("lumi_conv refuses what it cannot run", "[lumi_conv][gpu]") {
  REQUIRE_THROWS_WITH(passes::LumiConvPass(test::gpu(), {4, 4, 5, true}), Catch::Contains("1x1 or 3x3"));
  const passes::LumiConvPass pass(test::gpu(), {4, 4, 3, true});
  const std::vector<float> parameters(10);
  REQUIRE_THROWS_WITH(pass.upload_weights(test::gpu(), parameters, 0, "weights"), Catch::Contains("too few parameters"));
  const passes::LumiConvPass other(test::gpu(), {4, 20, 3, true});
  passes::LumiConvWeights two_groups =
      other.upload_weights(test::gpu(), std::vector<float>(other.shape().parameter_count()), 0, "weights");
  REQUIRE(two_groups.chunks.size() == 2);
  test::PassHarness gpu("lumi_conv refusal");
  const passes::LumiTensor small(1, 4, 3, 3);
  REQUIRE_THROWS_WITH(pass.add_to(gpu.graph(), "lumi_conv", test::input_tensor(gpu, "source", small), two_groups,
                                  test::output_tensor(gpu, "result", 1, 4, 3, 3), 3, 3, 1),
                      Catch::Contains("weights for 2 chunks"));
}
