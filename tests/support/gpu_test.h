#pragma once
// Shared by the GPU tests: one Vulkan context per test process, validation layer on; helpers
// for random images and for comparing a GPU result with its C++ reference.
#include <catch2/catch.hpp>

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "image/host_image.h"
#include "vulkan/context.h"

namespace rt::test {

// The process's context (created on first use): validation on, any device (REMOTETOUCH_DEVICE
// picks one), synchronization validation with REMOTETOUCH_SYNC_VALIDATION=1.
vk::Context& gpu();
void destroy_gpu();  // called by the test main, which then fails the run on validation errors
uint32_t gpu_validation_errors();

// Put at the start of a GPU test case: fails it if the validation layer reports an error
// while it runs.
class NoValidationErrors {
 public:
  NoValidationErrors();
  ~NoValidationErrors();

 private:
  uint32_t before_;
};

// Sizes that catch edge handling: 1x1, odd, not multiples of the 8x8 tile, one row, one column.
const std::vector<std::pair<uint32_t, uint32_t>>& odd_sizes();

HostImage random_image(std::mt19937& rng, uint32_t width, uint32_t height, PixelFormat format, float low = 0.0f,
                       float high = 1.0f);
HostImage filled_image(uint32_t width, uint32_t height, PixelFormat format, float value);

struct Comparison {
  size_t mismatches = 0;     // values outside |gpu - ref| <= abs_tol + rel_tol * |ref|
  size_t non_finite = 0;     // NaN or Inf in the GPU result
  double max_abs_error = 0;  // over all values
  std::string first_mismatch;
};

// Both comparisons throw, saying both shapes, when the images differ in width, height or channel
// count: a result of the wrong size is a failure of its own, never a count of mismatches.
Comparison compare(const HostImage& gpu, const HostImage& reference, double abs_tol, double rel_tol);
size_t count_non_finite(const HostImage& image);

// Per pixel: counts pixels with a value beyond abs + rel * |ref| in any channel, and non-finite
// values, for tests that allow a stated number of pixels to differ.
struct PixelComparison {
  size_t mismatched_pixels = 0;
  size_t non_finite = 0;
  double max_abs_error = 0;
};
PixelComparison compare_pixels(const HostImage& gpu, const HostImage& reference, double abs_tol, double rel_tol);

}  // namespace rt::test

// Both checks in one: same values within tolerance, and nothing non-finite on the GPU side.
#define RT_REQUIRE_MATCHES(gpu_image, reference_image, abs_tol, rel_tol)                          \
  do {                                                                                             \
    const auto rt_comparison = ::rt::test::compare((gpu_image), (reference_image), (abs_tol), (rel_tol)); \
    INFO("max abs error " << rt_comparison.max_abs_error << "; " << rt_comparison.first_mismatch); \
    REQUIRE(rt_comparison.non_finite == 0);                                                        \
    REQUIRE(rt_comparison.mismatches == 0);                                                        \
  } while (false)

// Nothing non-finite, and at most `allowed` pixels beyond the tolerance: for passes where a
// sample on a visibility or image border may fall either way.
#define RT_REQUIRE_MOSTLY_MATCHES(gpu_image, reference_image, abs_tol, rel_tol, allowed)                        \
  do {                                                                                                        \
    const auto rt_pixels = ::rt::test::compare_pixels((gpu_image), (reference_image), (abs_tol), (rel_tol));  \
    INFO(rt_pixels.mismatched_pixels << " of " << (gpu_image).width * (gpu_image).height                      \
                                     << " pixels differ, max " << rt_pixels.max_abs_error);                   \
    REQUIRE(rt_pixels.non_finite == 0);                                                                       \
    REQUIRE(rt_pixels.mismatched_pixels <= size_t(allowed));                                                  \
  } while (false)
