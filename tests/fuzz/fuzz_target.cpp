#include "fuzz_target.h"

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <unistd.h>

namespace rt::fuzz {
namespace {

std::map<std::string, Target>& targets() {
  static std::map<std::string, Target> table;
  return table;
}

void remove_work_dir() {
  std::error_code ignored;
  std::filesystem::remove_all(work_dir(), ignored);
}

}  // namespace

void fail(const std::string& what) {
  std::fprintf(stderr, "fuzz target failed: %s\n", what.c_str());
  std::abort();
}

const std::filesystem::path& work_dir() {
  static const std::filesystem::path dir = [] {
    const std::filesystem::path made =
        std::filesystem::temp_directory_path() / ("remotetouch-fuzz-" + std::to_string(::getpid()));
    std::filesystem::remove_all(made);
    std::filesystem::create_directories(made);
    std::atexit(remove_work_dir);
    return made;
  }();
  return dir;
}

void write_file(const std::filesystem::path& path, std::string_view bytes) {
  std::ofstream file(path, std::ios::binary | std::ios::trunc);
  file.write(bytes.data(), std::streamsize(bytes.size()));
  if (!file) fail("cannot write " + path.string());
}

std::filesystem::path assets_dir() { return RT_FUZZ_ASSETS_DIR; }

Registration::Registration(const char* name, Target target) { targets()[name] = target; }

Target find_target(const std::string& name) {
  const auto it = targets().find(name);
  return it == targets().end() ? nullptr : it->second;
}

std::string target_names() {
  std::string names;
  for (const auto& [name, target] : targets()) names += (names.empty() ? "" : ", ") + name;
  return names;
}

}  // namespace rt::fuzz
