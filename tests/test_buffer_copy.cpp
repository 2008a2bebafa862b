// buffer_copy pass (a roofline of the benchmarks): the copy must be exact, bit for bit, whatever
// the bits say (NaN and infinity patterns included), for any element count.
#include <cstring>
#include <limits>

#include "passes/buffer_copy.h"
#include "support/gpu_test.h"
#include "support/pass_harness.h"

using namespace rt;

namespace {

std::vector<uint32_t> run_gpu(const std::vector<uint32_t>& words, size_t room_words) {
  const passes::BufferCopyPass pass(test::gpu());
  test::PassHarness gpu("buffer_copy");
  vk::Buffer& destination = gpu.output_buffer<uint32_t>("destination", room_words);
  pass.add_to(gpu.graph(), gpu.input_buffer("source", words), destination, words.size() / 4 * 16);
  return gpu.run().values<uint32_t>("destination");
}

}  // namespace

TEST_CASE("buffer_copy reproduces random buffers of odd element counts exactly", "[buffer_copy][gpu]") {
  test::NoValidationErrors no_errors;
  std::mt19937 rng(21);
  for (const size_t elements : {1ul, 3ul, 255ul, 257ul, 4097ul, 70001ul}) {
    INFO(elements << " elements");
    std::vector<uint32_t> words(elements * 4);
    for (uint32_t& word : words) word = rng();
    CHECK(run_gpu(words, words.size()) == words);
  }
}

TEST_CASE("buffer_copy hard cases", "[buffer_copy][gpu]") {
  test::NoValidationErrors no_errors;
  SECTION("NaN and infinity bit patterns are copied, not normalised") {
    const float values[8] = {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(),
                             -std::numeric_limits<float>::infinity(), -0.0f, std::numeric_limits<float>::denorm_min(),
                             std::numeric_limits<float>::signaling_NaN(), 1.0f, 0.0f};
    std::vector<uint32_t> words(8);
    std::memcpy(words.data(), values, sizeof values);
    words[7] = 0x7fc01234u;  // a NaN with a payload
    CHECK(run_gpu(words, 8) == words);
  }
  SECTION("only the requested elements are written") {
    std::vector<uint32_t> words(12, 0xabcdef01u);
    const passes::BufferCopyPass pass(test::gpu());
    test::PassHarness gpu("buffer_copy part");
    const std::vector<uint32_t> zeros(12, 0u);
    vk::Buffer& destination = gpu.input_buffer("destination", zeros, true);
    pass.add_to(gpu.graph(), gpu.input_buffer("source", words), destination, 32);
    const std::vector<uint32_t> copied = gpu.run().values<uint32_t>("destination");
    for (size_t i = 0; i < 12; ++i) CHECK(copied[i] == (i < 8 ? 0xabcdef01u : 0u));
  }
  SECTION("sizes that are not whole elements, or too big, are refused") {
    const passes::BufferCopyPass pass(test::gpu());
    test::PassHarness gpu("buffer_copy refused");
    const std::vector<uint32_t> words(8, 1u);
    vk::Buffer& source = gpu.input_buffer("source", words);
    vk::Buffer& destination = gpu.output_buffer<uint32_t>("destination", 8);
    CHECK_THROWS_WITH(pass.add_to(gpu.graph(), source, destination, 20), Catch::Contains("16-byte"));
    CHECK_THROWS_WITH(pass.add_to(gpu.graph(), source, destination, 48), Catch::Contains("do not fit"));
  }
  SECTION("a dispatch is bounded however many elements") {
    CHECK(passes::buffer_copy_invocations(0) == 1);
    CHECK(passes::buffer_copy_invocations(1ull << 40) == 65535u * 256);
  }
}
