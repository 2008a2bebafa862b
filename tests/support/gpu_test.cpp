#include "support/gpu_test.h"

#include <cmath>
#include <memory>
#include <sstream>
#include <stdexcept>

namespace rt::test {
namespace {

std::unique_ptr<vk::Context>& context_slot() {
  static std::unique_ptr<vk::Context> context;
  return context;
}

std::atomic<uint32_t> all_validation_errors{0};

}  // namespace

vk::Context& gpu() {
  auto& context = context_slot();
  if (!context) {
    vk::ContextOptions options;
    options.validation = true;
    options.print_device = false;
    options.pipeline_cache_path = REMOTETOUCH_TEST_PIPELINE_CACHE;
    options.error_counter = &all_validation_errors;
    context = std::make_unique<vk::Context>(vk::apply_environment(options));
  }
  return *context;
}

void destroy_gpu() { context_slot().reset(); }

uint32_t gpu_validation_errors() { return all_validation_errors.load(); }

NoValidationErrors::NoValidationErrors() : before_(gpu().validation_errors()) {}

NoValidationErrors::~NoValidationErrors() {
  const uint32_t errors = gpu().validation_errors() - before_;
  CHECK(errors == 0);
}

const std::vector<std::pair<uint32_t, uint32_t>>& odd_sizes() {
  static const std::vector<std::pair<uint32_t, uint32_t>> sizes = {
      {1, 1}, {7, 5}, {641, 359}, {8, 8}, {9, 1}, {1, 13}, {33, 17}};
  return sizes;
}

HostImage random_image(std::mt19937& rng, uint32_t width, uint32_t height, PixelFormat format, float low, float high) {
  HostImage image(width, height, format);
  std::uniform_real_distribution<float> value(low, high);
  for (float& texel : image.texels) texel = value(rng);
  return image;
}

HostImage filled_image(uint32_t width, uint32_t height, PixelFormat format, float value) {
  return HostImage(width, height, format, value);
}

size_t count_non_finite(const HostImage& image) {
  size_t count = 0;
  for (float texel : image.texels) count += !std::isfinite(texel);
  return count;
}

namespace {

std::string shape_of(const HostImage& image) {
  return std::to_string(image.width) + "x" + std::to_string(image.height) + " with " + std::to_string(image.channels()) +
         (image.channels() == 1 ? " channel" : " channels") + " (" + format_name(image.format) + ")";
}

void require_same_shape(const char* comparison, const HostImage& gpu_image, const HostImage& reference) {
  const size_t values = size_t(reference.width) * reference.height * reference.channels();
  if (gpu_image.width != reference.width || gpu_image.height != reference.height ||
      gpu_image.channels() != reference.channels())
    throw std::invalid_argument(std::string(comparison) + ": the GPU image is " + shape_of(gpu_image) +
                                ", the reference " + shape_of(reference));
  if (gpu_image.texels.size() != values || reference.texels.size() != values)
    throw std::invalid_argument(std::string(comparison) + ": an image of " + shape_of(reference) + " holds " +
                                std::to_string(gpu_image.texels.size()) + " (GPU) and " +
                                std::to_string(reference.texels.size()) + " (reference) values, not " +
                                std::to_string(values));
}

}  // namespace

Comparison compare(const HostImage& gpu_image, const HostImage& reference, double abs_tol, double rel_tol) {
  require_same_shape("compare", gpu_image, reference);
  Comparison result;
  result.non_finite = count_non_finite(gpu_image);
  const uint32_t channels = reference.channels();
  for (size_t i = 0; i < reference.texels.size(); ++i) {
    const double got = gpu_image.texels[i], want = reference.texels[i];
    const double error = std::abs(got - want);
    if (std::isfinite(error)) result.max_abs_error = std::max(result.max_abs_error, error);
    if (!(error <= abs_tol + rel_tol * std::abs(want))) {
      if (result.mismatches++ == 0) {
        std::ostringstream where;
        const size_t texel = i / channels;
        where << "first mismatch at (" << texel % reference.width << ", " << texel / reference.width << ") channel "
              << i % channels << ": gpu " << got << ", reference " << want;
        result.first_mismatch = where.str();
      }
    }
  }
  return result;
}

PixelComparison compare_pixels(const HostImage& gpu_image, const HostImage& reference, double abs_tol, double rel_tol) {
  require_same_shape("compare_pixels", gpu_image, reference);
  PixelComparison result;
  const uint32_t channels = reference.channels();
  for (size_t pixel = 0; pixel < size_t(reference.width) * reference.height; ++pixel) {
    bool mismatch = false;
    for (uint32_t c = 0; c < channels; ++c) {
      const double g = gpu_image.texels[pixel * channels + c], r = reference.texels[pixel * channels + c];
      if (!std::isfinite(g)) {
        ++result.non_finite;
        continue;
      }
      const double error = std::abs(g - r);
      result.max_abs_error = std::max(result.max_abs_error, error);
      if (!(error <= abs_tol + rel_tol * std::abs(r))) mismatch = true;
    }
    result.mismatched_pixels += mismatch;
  }
  return result;
}

}  // namespace rt::test
