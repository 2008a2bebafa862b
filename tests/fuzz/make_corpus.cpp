// Writes the fuzzer's seed corpus (tests/fuzz/corpus/): valid messages of every type and a few
// broken ones. With --check DIR it checks a corpus instead: valid_* must decode, broken_* must be
// rejected, so a change of the wire format that forgets the corpus fails a test.
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>

#include "net/message_codec.h"
#include "net_test_messages.h"

using namespace rt;
using namespace rt::net;

namespace {

std::map<std::string, std::vector<uint8_t>> corpus() {
  std::map<std::string, std::vector<uint8_t>> out;
  out["valid_eye"] = encode_message(EyeMessage{123456, {0.02, 0.1, -0.7}, true});
  out["valid_eye_untracked"] = encode_message(EyeMessage{123457, {0, 0, 0}, false});
  out["valid_heartbeat"] = encode_message(HeartbeatMessage{99, 7});
  out["valid_touch_start"] = encode_message(TouchEventMessage{5, TouchEventMessage::Kind::Start, 0});
  out["valid_touch_end"] = encode_message(TouchEventMessage{6, TouchEventMessage::Kind::End, 1});
  out["valid_skeleton_two_hands"] = encode_message(test::test_skeleton(1000));
  out["valid_skeleton_no_hands"] = encode_message(SkeletonMessage{1000, {}});
  SkeletonMessage one = test::test_skeleton(1001);
  one.hands.resize(1);
  out["valid_skeleton_one_hand"] = encode_message(one);
  out["valid_portrait_16x12"] = encode_message(test::test_portrait(16, 12, 1), {.jpeg_quality = 60});
  out["valid_portrait_5x3"] = encode_message(test::test_portrait(5, 3, 2), {.jpeg_quality = 90});
  out["valid_portrait_1x1"] = encode_message(test::test_portrait(1, 1, 3));

  auto broken = out["valid_heartbeat"];
  broken[0] = 'X';
  out["broken_magic"] = broken;
  broken = out["valid_eye"];
  broken.pop_back();
  out["broken_truncated_eye"] = broken;
  broken = out["valid_portrait_16x12"];
  broken.resize(broken.size() - 40);
  out["broken_truncated_portrait"] = broken;
  broken = out["valid_portrait_16x12"];
  const uint32_t wrong_width = 17;
  std::memcpy(broken.data() + kHeaderSize + 16, &wrong_width, 4);
  out["broken_portrait_size_mismatch"] = broken;
  broken = out["valid_skeleton_two_hands"];
  const double nan = std::nan("");
  std::memcpy(broken.data() + kHeaderSize + 9 + 17, &nan, 8);
  out["broken_skeleton_nan"] = broken;
  broken = out["valid_touch_start"];
  broken.push_back(0);
  out["broken_trailing"] = broken;
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc == 3 && std::string(argv[1]) == "--check") {
    int failures = 0;
    for (const auto& entry : std::filesystem::directory_iterator(argv[2])) {
      std::ifstream file(entry.path(), std::ios::binary);
      std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
      const std::string name = entry.path().filename().string();
      const DecodeResult result = decode_message(bytes);
      const bool expect_ok = name.rfind("valid_", 0) == 0;
      if (result.ok() != expect_ok) {
        std::cerr << name << ": " << (result.ok() ? "decodes, expected a rejection" : "rejected: " + result.error.message) << "\n";
        ++failures;
      }
    }
    std::cout << (failures ? "corpus check failed\n" : "corpus ok\n");
    return failures ? 1 : 0;
  }
  if (argc != 2) {
    std::cerr << "usage: net_fuzz_corpus OUT_DIR | --check DIR\n";
    return 2;
  }
  std::filesystem::create_directories(argv[1]);
  for (const auto& [name, bytes] : corpus()) {
    std::ofstream(std::filesystem::path(argv[1]) / name, std::ios::binary)
        .write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
  }
  std::cout << "wrote " << corpus().size() << " seeds to " << argv[1] << "\n";
  return 0;
}
