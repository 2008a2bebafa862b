#pragma once
// A Janus server for a test, inside the network namespace that tests/cli/in_network_namespace.sh
// made for it: Janus will not use loopback for media, so its ICE uses the namespace's own address
// (RT_TEST_NAMESPACE_ADDRESS), which nothing outside the namespace can reach. Its WebSocket API
// listens on 127.0.0.1:8188 there; its configuration and log go to the test's output folder.
// Tests skip, saying why, where the namespace or /usr/bin/janus is missing.
#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <asio.hpp>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
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
    std::filesystem::create_directories(folder);
    const std::string lib = "/usr/lib/x86_64-linux-gnu/janus/";
    std::ofstream(folder / "janus.jcfg")
        << "general: {\n  configs_folder = \"" << folder.string() << "\"\n  plugins_folder = \"" << lib
        << "plugins\"\n  transports_folder = \"" << lib << "transports\"\n  events_folder = \"" << lib
        << "events\"\n  loggers_folder = \"" << lib << "loggers\"\n  debug_level = 4\n  session_timeout = 60\n}\n"
        << "media: { rtp_port_range = \"20000-20999\" }\n"
        << "nat: { ice_enforce_list = \"" << address << "\" }\n"
        << "plugins: { disable = \"libjanus_audiobridge.so,libjanus_duktape.so,libjanus_echotest.so,libjanus_lua.so,"
           "libjanus_nosip.so,libjanus_recordplay.so,libjanus_sip.so,libjanus_streaming.so,libjanus_textroom.so,"
           "libjanus_videocall.so,libjanus_voicemail.so\" }\n"
        << "transports: { disable = \"libjanus_http.so,libjanus_mqtt.so,libjanus_nanomsg.so,libjanus_pfunix.so,"
           "libjanus_rabbitmq.so\" }\n"
        << "events: { broadcast = false }\n";
    std::ofstream(folder / "janus.transport.websockets.jcfg")
        << "general: { json = \"plain\" ws = true ws_port = 8188 ws_ip = \"127.0.0.1\" wss = false }\n"
        << "admin: { admin_ws = false }\n";
    std::ofstream(folder / "janus.plugin.videoroom.jcfg") << "general: { }\n";
    const std::vector<std::string> args = {kJanusServer, "-F", folder.string(), "-C", (folder / "janus.jcfg").string(), "-i",
                                           address, "-L", (folder / "janus.log").string(), "-o", "-N"};
    pid_ = fork();
    if (pid_ == 0) {
      const int null = open("/dev/null", O_WRONLY);
      dup2(null, 1);
      dup2(null, 2);
      std::vector<char*> argv;
      for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
      argv.push_back(nullptr);
      execv(kJanusServer, argv.data());
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
