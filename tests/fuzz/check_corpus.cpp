// Runs a fuzz target's committed corpus through the engine's own (GCC) build: every input must
// pass the target's checks, a valid_* input must be accepted and a broken_* one refused (its
// refusal printed), so that a change of a format that forgets its corpus, or a crash the fuzzer
// once found, fails a test. usage: fuzz_corpus_check TARGET DIR
#include <algorithm>
#include <fstream>
#include <iostream>
#include <iterator>
#include <vector>

#include "fuzz_target.h"

int main(int argc, char** argv) {
  if (argc != 3) {
    std::cerr << "usage: fuzz_corpus_check TARGET DIR (targets: " << rt::fuzz::target_names() << ")\n";
    return 2;
  }
  const rt::fuzz::Target target = rt::fuzz::find_target(argv[1]);
  if (!target) {
    std::cerr << "no fuzz target '" << argv[1] << "' (targets: " << rt::fuzz::target_names() << ")\n";
    return 2;
  }
  std::vector<std::filesystem::path> inputs;
  for (const auto& entry : std::filesystem::directory_iterator(argv[2])) inputs.push_back(entry.path());
  std::sort(inputs.begin(), inputs.end());
  int failures = 0;
  for (const std::filesystem::path& path : inputs) {
    std::ifstream file(path, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
    const std::string name = path.filename().string();
    const bool expect_ok = name.rfind("valid_", 0) == 0;
    if (!expect_ok && name.rfind("broken_", 0) != 0) {
      std::cerr << name << ": a corpus file's name starts with valid_ or broken_\n";
      ++failures;
      continue;
    }
    const rt::fuzz::Outcome outcome = target(bytes);
    if (outcome.accepted != expect_ok) {
      std::cerr << name << ": " << (outcome.accepted ? "accepted, expected a refusal" : "refused: " + outcome.refusal) << "\n";
      ++failures;
    } else {
      std::cout << name << ": " << (outcome.accepted ? "accepted" : "refused: " + outcome.refusal) << "\n";
    }
  }
  if (inputs.empty()) {
    std::cerr << "no inputs in " << argv[2] << "\n";
    ++failures;
  }
  std::cout << (failures ? "corpus check failed\n" : "corpus ok\n");
  return failures ? 1 : 0;
}
