#include "support/output_dir.h"

namespace rt::test {

std::filesystem::path output_dir(std::string_view test_name) {
  return std::filesystem::path(REMOTETOUCH_TEST_OUTPUT_ROOT) / test_name;
}

}  // namespace rt::test
