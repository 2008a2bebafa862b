// `remotetouch demo`: both sites of a scene, each its own process (`remotetouch site`), talking
// over loopback through the encrypted session (optionally through the fault proxy), as two PCs
// would over a LAN. The parent makes the session key, starts site A (listener), learns its port,
// starts site B (connector), shows progress, then merges both sites' events and metrics and
// measures each site's displayed frames against the other site's ground truth.
#include "app/two_site_demo.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "evaluation/touch_phase.h"
#include "net/fault_proxy.h"
#include "pipeline/hand_settings.h"
#include "pipeline/ibr_settings.h"
#include "net/secure_channel.h"
#include "session/event_log.h"
#include "session/output_folder_lock.h"
#include "site/site_options.h"
#include "sim/scene.h"
#include "site/closing_table.h"
#include "site/displayed_truth.h"
#include "time/monotonic_clock.h"

extern char** environ;

namespace rt::app {

namespace {

struct Child {
  std::string site;
  pid_t pid = -1;
  int stdout_fd = -1;
  std::string buffer;
  uint64_t progress = 0, total = 0;
  bool eof = false;
  bool done = false;  // said "done": its outputs are written
  int exit_code = -1;
};

Child spawn_site(const std::string& site, const std::vector<std::string>& args) {
  int pipe_fds[2];
  if (pipe(pipe_fds) != 0) throw std::runtime_error("demo: cannot make a pipe for site " + site);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, pipe_fds[1], STDOUT_FILENO);
  posix_spawn_file_actions_addclose(&actions, pipe_fds[0]);
  posix_spawn_file_actions_addclose(&actions, pipe_fds[1]);
  const std::string self = std::filesystem::read_symlink("/proc/self/exe").string();
  std::vector<char*> argv;
  argv.push_back(const_cast<char*>(self.c_str()));
  for (const auto& arg : args) argv.push_back(const_cast<char*>(arg.c_str()));
  argv.push_back(nullptr);
  Child child;
  child.site = site;
  const int error = posix_spawn(&child.pid, self.c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  close(pipe_fds[1]);
  if (error != 0) {
    close(pipe_fds[0]);
    throw std::runtime_error("demo: cannot start site " + site + ": " + std::strerror(error));
  }
  child.stdout_fd = pipe_fds[0];
  return child;
}

// Reads what is there; returns complete lines.
std::vector<std::string> read_lines(Child& child) {
  std::vector<std::string> lines;
  char data[4096];
  const ssize_t n = read(child.stdout_fd, data, sizeof data);
  if (n <= 0) {
    child.eof = true;
    if (!child.buffer.empty()) lines.push_back(std::move(child.buffer));
    child.buffer.clear();
    return lines;
  }
  child.buffer.append(data, size_t(n));
  size_t start = 0;
  for (size_t newline; (newline = child.buffer.find('\n', start)) != std::string::npos; start = newline + 1)
    lines.push_back(child.buffer.substr(start, newline - start));
  child.buffer.erase(0, start);
  return lines;
}

void handle_line(Child& child, const std::string& line) {
  unsigned long long done = 0, total = 0;
  if (std::sscanf(line.c_str(), "progress %llu %llu", &done, &total) == 2) {
    child.progress = done;
    child.total = total;
  } else if (!line.empty()) {
    std::cerr << "[site " << child.site << "] " << line << "\n";
  }
}

void draw_progress(const std::vector<Child*>& children, bool tty) {
  static int last_decile = -1;
  std::ostringstream text;
  double fraction = 1.0;
  for (const Child* child : children) {
    const double f = child->total ? double(child->progress) / double(child->total) : 0.0;
    fraction = std::min(fraction, f);
    text << "  site " << child->site << " " << child->progress << "/" << child->total;
  }
  const int width = 30, filled = int(std::lround(fraction * width));
  const std::string bar = "[" + std::string(size_t(filled), '#') + std::string(size_t(width - filled), '.') + "]";
  if (tty) {
    std::cerr << "\r" << bar << text.str() << std::flush;
  } else if (int(fraction * 10) != last_decile) {  // a log file gets a line per tenth
    last_decile = int(fraction * 10);
    std::cerr << bar << text.str() << "\n";
  }
}

int wait_child(Child& child) {
  int status = 0;
  if (waitpid(child.pid, &status, 0) < 0) return -1;
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  return 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
}

// Reads `child`'s lines until one starts with `prefix`; the rest of that line. Throws if the
// child ends first or the wait passes `timeout_s`.
std::string wait_for_line(Child& child, const std::string& prefix, double timeout_s) {
  const uint64_t deadline = monotonic_now_us() + uint64_t(timeout_s * 1e6);
  while (monotonic_now_us() < deadline) {
    pollfd fd{child.stdout_fd, POLLIN, 0};
    if (poll(&fd, 1, 200) <= 0) continue;
    for (const std::string& line : read_lines(child)) {
      if (line.rfind(prefix, 0) == 0) return line.substr(prefix.size());
      handle_line(child, line);
    }
    // The site has said why on stderr, which the demo shares: point there, not at the protocol.
    if (child.eof) throw std::runtime_error("site " + child.site + " ended before it was ready (its error is above)");
  }
  throw std::runtime_error("site " + child.site + " was not listening within " + std::to_string(int(timeout_s)) + " s");
}

nlohmann::json read_json(const std::filesystem::path& path) {
  std::ifstream file(path);
  if (!file) throw std::runtime_error("demo: missing " + path.string());
  nlohmann::json json = nlohmann::json::parse(file, nullptr, false);
  if (json.is_discarded()) throw std::runtime_error("demo: " + path.string() + " is not JSON");
  return json;
}

void print_summary(const nlohmann::json& metrics) {
  std::printf("\n");
  site::print_table_row("", {"site A", "site B"});
  auto row = [&](const std::string& name, const std::string& va, const std::string& vb) { site::print_table_row(name, {va, vb}); };
  const auto rows_a = site::closing_rows(metrics["sites"]["A"]);
  const auto rows_b = site::closing_rows(metrics["sites"]["B"]);
  for (size_t i = 0; i < rows_a.size(); ++i) row(rows_a[i].first, rows_a[i].second, rows_b[i].second);
  row("PSNR final composite dB (mean)",
      site::table_cell(metrics["psnr_db"]["A"]["final_db"]) + " (" + site::table_cell(metrics["psnr_db"]["A"]["mean_db"]) + ")",
      site::table_cell(metrics["psnr_db"]["B"]["final_db"]) + " (" + site::table_cell(metrics["psnr_db"]["B"]["mean_db"]) + ")");
  // What the remote user sees of the hand and forearm, per touch phase.
  for (const char* phase : evaluation::kTouchPhaseNames) {
    const nlohmann::json::json_pointer path("/hand_arm/" + std::string(phase));
    auto figures = [&](const nlohmann::json& site) {
      if (!site.contains(path)) return std::string("-");
      const nlohmann::json& f = site.at(path);
      return site::table_cell(f.value("psnr_hand_arm_db", nlohmann::json())) + "/" + site::table_cell(f.value("de_hand", nlohmann::json())) + " (" +
             site::table_cell(f.value("frames", nlohmann::json()), "%.0f") + ")";
    };
    row(std::string("hand+arm dB/CIEDE2000 (frames) ") + phase, figures(metrics["psnr_db"]["A"]),
        figures(metrics["psnr_db"]["B"]));
  }
  std::printf("paper (RTX 3090): portrait ~400 ms, hand ~250 ms, touch to motor ~60 ms, 30 fps\n");
}

}  // namespace

int run_two_site_demo(const DemoOptions& options) {
  sim::resolve_scene(options.scene);  // an unknown scene is refused here, before any site starts
  const std::filesystem::path out = options.run.out;
  // Before anything in it is removed: another demo may be writing there.
  session::OutputFolderLock out_lock(out, "--out");
  for (const char* site : {"site_A", "site_B"}) std::filesystem::remove_all(out / site);
  // A fresh key each run, created owner-only in one step (an old one, or a link in its place,
  // is removed, never written through).
  const std::filesystem::path key_file = out / "session.key";
  std::filesystem::remove(key_file);
  net::write_new_session_key_file(key_file);

  auto site_args = [&](const std::string& site) {
    std::vector<std::string> args = {"site", "--site", site, "--scene", options.scene, "--key-file", key_file.string(),
                                     "--out", (out / ("site_" + site)).string(), "--width", std::to_string(options.run.width),
                                     "--height", std::to_string(options.run.height),
                                     // Two sites on one machine cannot share one motor board.
                                     "--motor", "simulated", "--progress-lines", "--transport", options.transport};
    if (options.frames_given) args.insert(args.end(), {"--frames", std::to_string(options.run.frames)});
    if (options.packet_loss >= 0) args.insert(args.end(), {"--simulated-loss", std::to_string(options.packet_loss)});
    if (options.time_scale > 0) args.insert(args.end(), {"--time-scale", std::to_string(options.time_scale)});
    if (options.resolution_scale > 0) args.insert(args.end(), {"--resolution-scale", std::to_string(options.resolution_scale)});
    if (!options.run.device.empty()) args.insert(args.end(), {"--device", options.run.device});
    if (options.run.validation) args.push_back("--validation");
    if (options.run.profile) args.push_back("--profile");
    if (options.run.capture_frame >= 0) args.insert(args.end(), {"--capture-frame", std::to_string(options.run.capture_frame)});
    const bool window = site::parse_display_mode(options.display, site::display_present()) != site::DisplayMode::Headless;
    args.insert(args.end(), {"--display", window ? "both" : "headless", "--present-mode", options.present_mode});
    args.insert(args.end(), {"--audio-in", options.sound, "--audio-out", options.sound});
    if (options.noise_suppression) args.push_back("--noise-suppression");
    if (options.gain_control) args.push_back("--gain-control");
    if (options.no_lip_sync) args.push_back("--no-lip-sync");
    const std::filesystem::path& replay = site == "A" ? options.replay_a : options.replay_b;
    if (!replay.empty()) args.insert(args.end(), {"--replay", replay.string()});
    // The image-based model's, the hand's and the touch options, as the demo was given them.
    args.insert(args.end(), options.quality_arguments.begin(), options.quality_arguments.end());
    for (const std::string& arg : config::knob_arguments(pipeline::ibr_knobs(), options.ibr, pipeline::IbrSettings{}))
      args.push_back(arg);
    for (const std::string& arg : config::knob_arguments(pipeline::hand_knobs(), options.hand,
                                                         pipeline::HandRendererOptions{}, pipeline::kHandOptionPrefix))
      args.push_back(arg);
    for (const std::string& arg : config::knob_arguments(touch_knobs(), options.touch, TouchSettings{})) args.push_back(arg);
    return args;
  };

  std::cerr << "demo: scene " << options.scene << ", two sites as two processes over loopback ("
            << (options.transport == "webrtc" ? "WebRTC call" : "direct session") << "), " << options.run.width << "x"
            << options.run.height << ", time scale "
            << (options.time_scale > 0 ? std::to_string(options.time_scale) : std::string("by the device")) << "\n";
  std::vector<std::string> args_a = site_args("A");
  args_a.insert(args_a.end(), {"--listen", "127.0.0.1:0"});
  Child a = spawn_site("A", args_a);
  std::optional<Child> b;
  std::unique_ptr<net::FaultProxy> proxy;
  try {
    const uint16_t port = uint16_t(std::stoi(wait_for_line(a, "listening on ", 300.0)));
    uint16_t peer_port = port;
    const bool faults = options.disconnect_after_ms || options.delay_ms > 0 || options.jitter_ms > 0 || options.loss > 0;
    if (faults) {
      net::FaultOptions fault;
      fault.delay = std::chrono::milliseconds(options.delay_ms);
      fault.jitter = std::chrono::milliseconds(options.jitter_ms);
      fault.loss = options.loss;
      proxy = std::make_unique<net::FaultProxy>("127.0.0.1", port, fault);
      proxy->start();
      peer_port = proxy->port();
    }
    std::vector<std::string> args_b = site_args("B");
    args_b.insert(args_b.end(), {"--peer", "127.0.0.1:" + std::to_string(peer_port)});
    b = spawn_site("B", args_b);
  } catch (...) {
    kill(a.pid, SIGTERM);
    wait_child(a);
    throw;
  }

  const bool tty = isatty(STDERR_FILENO);
  std::vector<Child*> children = {&a, &*b};
  bool disconnected = false;
  uint64_t connected_at = 0, outage_ends_at = 0;
  while (!a.eof || !b->eof) {
    std::vector<pollfd> fds;
    for (Child* child : children)
      if (!child->eof) fds.push_back({child->stdout_fd, POLLIN, 0});
    poll(fds.data(), fds.size(), 100);
    for (Child* child : children) {
      if (child->eof) continue;
      pollfd fd{child->stdout_fd, POLLIN, 0};
      if (poll(&fd, 1, 0) <= 0) continue;
      for (const std::string& line : read_lines(*child)) {
        if (line == "connected" && !connected_at) connected_at = monotonic_now_us();
        if (line == "done") child->done = true;
        handle_line(*child, line);
      }
      // A site that ends without finishing fails the demo at once, named as the one that failed;
      // its peer would otherwise wait out its connect timeout and be reported instead.
      if (child->eof && !child->done) {
        close(child->stdout_fd);
        child->stdout_fd = -1;
        child->exit_code = wait_child(*child);
        if (child->exit_code == 0) continue;
        if (tty) std::cerr << "\n";
        std::cerr << "demo: site " << child->site << " failed (exit status " << child->exit_code
                  << ") before it finished; stopping the other site\n";
        for (Child* other : children)
          if (other != child && other->stdout_fd >= 0) {
            kill(other->pid, SIGTERM);
            close(other->stdout_fd);
            other->stdout_fd = -1;
            wait_child(*other);
          }
        if (proxy) proxy->stop();
        return 1;
      }
    }
    draw_progress(children, tty);
    if (proxy && options.disconnect_after_ms && !disconnected && connected_at &&
        monotonic_now_us() - connected_at > uint64_t(*options.disconnect_after_ms) * 1000) {
      std::cerr << (tty ? "\n" : "") << "demo: fault proxy cuts the connection"
                << (options.outage_ms > 0 ? " for " + std::to_string(options.outage_ms) + " ms" : std::string()) << "\n";
      if (options.outage_ms > 0) {
        proxy->set_blackhole(true);  // the reconnection attempts go unanswered until the outage ends
        outage_ends_at = monotonic_now_us() + uint64_t(options.outage_ms) * 1000;
      }
      proxy->disconnect_now();
      disconnected = true;
    }
    if (proxy && outage_ends_at && monotonic_now_us() >= outage_ends_at) {
      std::cerr << (tty ? "\n" : "") << "demo: fault proxy restores the link\n";
      proxy->set_blackhole(false);
      outage_ends_at = 0;
    }
  }
  if (tty) std::cerr << "\n";
  for (Child* child : children)
    if (child->stdout_fd >= 0) {
      close(child->stdout_fd);
      child->exit_code = wait_child(*child);
    }
  nlohmann::json fault_counts;
  if (proxy) {
    fault_counts = proxy->counts().to_json();
    proxy->stop();
  }
  // Known issue: lavapipe (Mesa 22.3) now and then crashes inside vkDestroyDevice when a site
  // process tears its context down (about 1 run in 20 under load; backtrace: Context::release ->
  // libvulkan_lvp.so). A site that crashed after saying "done" has written everything, so the run
  // counts, with a warning here and in metrics.json; any other failure fails the demo.
  nlohmann::json teardown_crashes = nlohmann::json::object();
  for (Child* child : children)
    if (child->exit_code != 0) {
      if (child->done && child->exit_code > 128) {
        std::cerr << "demo: warning: site " << child->site << " crashed during its Vulkan teardown (signal "
                  << child->exit_code - 128 << ") after writing its outputs\n";
        teardown_crashes[child->site] = child->exit_code - 128;
        continue;
      }
      std::cerr << "demo: site " << child->site << " failed (exit status " << child->exit_code << ")\n";
      return 1;
    }

  // Both sites' events on one time line (one machine: one monotonic clock).
  std::vector<nlohmann::json> events = session::read_events(out / "site_A" / "events.jsonl");
  for (auto& event : session::read_events(out / "site_B" / "events.jsonl")) events.push_back(std::move(event));
  std::stable_sort(events.begin(), events.end(),
                   [](const auto& x, const auto& y) { return x["t_us"].template get<uint64_t>() < y["t_us"].template get<uint64_t>(); });
  {
    std::ofstream merged(out / "events.jsonl");
    for (const auto& event : events)
      if (event.value("event", "") != "net_log") merged << event.dump() << "\n";
  }

  nlohmann::json metrics;
  metrics["scene"] = options.scene;
  metrics["transport"] = options.transport;
  if (options.packet_loss >= 0) metrics["packet_loss"] = options.packet_loss;
  metrics["width"] = options.run.width;
  metrics["height"] = options.run.height;
  metrics["quality"] = options.quality;
  metrics["sites"]["A"] = read_json(out / "site_A" / "metrics.json");
  metrics["sites"]["B"] = read_json(out / "site_B" / "metrics.json");
  metrics["time_scale"] = metrics["sites"]["A"].value("time_scale", nlohmann::json());
  // Site A shows B's user: compare with B's ground truth, and the other way round.
  metrics["psnr_db"]["A"] = site::measure_displayed_frames(out / "site_A", out / "site_B");
  metrics["psnr_db"]["B"] = site::measure_displayed_frames(out / "site_B", out / "site_A");
  metrics["psnr_note"] =
      "each site's displayed composite against the simulator's ground truth of the other site's user for the same "
      "captured frame, over the same background (the truth has no sensor effects); hand_arm: per touch phase, on the "
      "region of the remote user's hand and forearm reaching for the glass (PSNR) and its fully covered hand pixels "
      "(CIEDE2000)";
  if (proxy) metrics["fault_proxy"] = fault_counts;
  if (!teardown_crashes.empty()) metrics["teardown_crash_signal"] = teardown_crashes;
  std::ofstream(out / "metrics.json") << metrics.dump(2) << "\n";
  print_summary(metrics);
  std::printf("written to %s: site_A/ and site_B/ (frames/*.png, site.mp4, truth/), events.jsonl, metrics.json\n",
              out.string().c_str());
  return 0;
}

}  // namespace rt::app
