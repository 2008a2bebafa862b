// The test main: runs Catch2, then destroys the GPU context and fails the whole run if the
// validation layer reported any error, including those raised at device destruction.
#include <iostream>

#include "support/catch_session.h"
#include "support/gpu_test.h"

int main(int argc, char** argv) {
  const int result = rt::test::run_catch_session(argc, argv);
  rt::test::destroy_gpu();
  if (const uint32_t errors = rt::test::gpu_validation_errors(); errors > 0) {
    std::cerr << "FAILED: the Vulkan validation layer reported " << errors << " error(s)\n";
    return result == 0 ? 1 : result;
  }
  return result;
}
