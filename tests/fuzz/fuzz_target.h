#pragma once
// What every fuzz target of tests/fuzz/ shares. A target is one function from an input's bytes to
// an Outcome; RT_FUZZ_TARGET makes it a libFuzzer entry point in the clang build (tests/fuzz/
// CMakeLists.txt) and registers it by name in the GCC build's corpus checker (check_corpus.cpp),
// so that the committed corpora run through the very parsers the engine ships.
//
// What a target asserts is what must hold for any input: no crash and no sanitizer report (the
// clang build), and a refusal is a std::exception whose message says why. Anything else thrown, or
// an empty message, aborts with a line saying so, and libFuzzer keeps the input.
#include <cstddef>
#include <cstdint>
#include <exception>
#include <filesystem>
#include <string>
#include <string_view>
#include <type_traits>

namespace rt::fuzz {

struct Outcome {
  bool accepted = false;
  std::string refusal;  // the exception's message when refused
};

[[noreturn]] void fail(const std::string& what);

// Runs `parse` (which returns nothing); a std::exception of type Refusal is the input refused and
// must carry a message; any other exception fails the target.
template <class Refusal = std::exception, class Parse>
Outcome outcome_of(Parse&& parse, const char* refusal_type = "std::exception") {
  try {
    parse();
    return {true, {}};
  } catch (const std::exception& error) {
    if constexpr (!std::is_same_v<Refusal, std::exception>)
      if (!dynamic_cast<const Refusal*>(&error))
        fail(std::string("refused with an exception other than ") + refusal_type + ": " + error.what());
    const std::string message = error.what();
    if (message.empty()) fail(std::string("refused with an empty message (") + refusal_type + ")");
    return {false, message};
  } catch (...) {
    fail("threw something that is not a std::exception");
  }
}

// A folder of this process's own (the process id in its name), made on first use and removed at exit.
const std::filesystem::path& work_dir();
void write_file(const std::filesystem::path& path, std::string_view bytes);
// The repository's assets/ (a path compiled in by both builds).
std::filesystem::path assets_dir();

using Target = Outcome (*)(std::string_view input);
struct Registration {
  Registration(const char* name, Target target);
};
Target find_target(const std::string& name);  // nullptr when there is none
std::string target_names();

}  // namespace rt::fuzz

#ifdef RT_LIBFUZZER
#define RT_FUZZ_TARGET(name, function)                                               \
  extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {          \
    function(std::string_view(reinterpret_cast<const char*>(data), size));           \
    return 0;                                                                        \
  }
#else
#define RT_FUZZ_TARGET(name, function) static const ::rt::fuzz::Registration rt_fuzz_registration_##function(name, function);
#endif
