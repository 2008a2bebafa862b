#pragma once
// A Janus server for a test (tests/cli/start_janus.sh), inside the network namespace that
// tests/cli/in_network_namespace.sh made for it: Janus will not use loopback for media, so its ICE
// uses the namespace's own address (RT_TEST_NAMESPACE_ADDRESS), which nothing outside the
// namespace can reach. Its WebSocket API listens on 127.0.0.1:8188 there; its configuration and
// log go to the test's output folder.
// Tests skip, saying why, where the namespace or /usr/bin/janus is missing.
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <asio.hpp>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>
#include <thread>
#include <vector>

namespace rt::test {

constexpr const char* kJanusServer = "/usr/bin/janus";

// The namespace's address, or why a Janus test cannot run here.
inline std::optional<std::string> janus_test_address(std::string* why) {
  const char* address = std::getenv("RT_TEST_NAMESPACE_ADDRESS");
  if (!address || !*address) {
    *why = "not in a network namespace of the test's own (run through tests/cli/in_network_namespace.sh, as ctest does)";
    return std::nullopt;
  }
  if (!std::filesystem::exists(kJanusServer)) {
    *why = std::string(kJanusServer) + " is missing: apt-get install janus (scripts/packages.txt lists it)";
    return std::nullopt;
  }
  return std::string(address);
}

class JanusInNamespace {
 public:
  JanusInNamespace(const std::filesystem::path& folder, const std::string& address) {
    const char* from_wrapper = std::getenv("RT_TEST_START_JANUS");
    const std::string script = from_wrapper ? from_wrapper : "tests/cli/start_janus.sh";
    pid_ = fork();
    if (pid_ == 0) {
      execl(script.c_str(), script.c_str(), folder.c_str(), address.c_str(), static_cast<char*>(nullptr));
      _exit(127);
    }
  }
  ~JanusInNamespace() {
    if (pid_ <= 0) return;
    kill(pid_, SIGTERM);
    int status = 0;
    waitpid(pid_, &status, 0);
  }
  // True once its WebSocket port accepts a connection (within `timeout`).
  bool wait_ready(std::chrono::milliseconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < deadline) {
      int status = 0;
      if (pid_ <= 0 || waitpid(pid_, &status, WNOHANG) != 0) return false;
      asio::io_context io;
      asio::ip::tcp::socket socket(io);
      asio::error_code ec;
      socket.connect({asio::ip::make_address("127.0.0.1"), 8188}, ec);
      if (!ec) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    return false;
  }
  std::string url() const { return "ws://127.0.0.1:8188"; }

 private:
  pid_t pid_ = -1;
};

}  // namespace rt::test
