#pragma once
// Where a test writes its files: a folder of its own under the build tree's test-out/, so that
// nothing lands in the source tree and two tests never share a folder.
#include <filesystem>
#include <string_view>

namespace rt::test {

std::filesystem::path output_dir(std::string_view test_name);

}  // namespace rt::test
