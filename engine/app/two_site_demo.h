#pragma once
// `remotetouch demo` (both sites of a scene as two processes over loopback, with a progress bar,
// merged events, metrics and a summary table) and `remotetouch site` (one site, for a real
// two-machine set-up or as the demo's child).
#include <CLI/CLI.hpp>

#include <optional>

#include "app/options.h"
#include "site/site_run.h"

namespace rt::app {

struct DemoOptions {
  RunOptions run;
  bool frames_given = false;
  std::string scene = "clap";
  double time_scale = 0.25;  // the default scene plays at quarter speed: lavapipe renders ~1 frame/s per site
  double resolution_scale = 0.0;  // 0 = the scene's own
  // Faults on the link (through net::FaultProxy; none by default).
  std::optional<int> disconnect_after_ms;
  int outage_ms = 0;  // after the cut, the link stays silent this long (reconnects fail meanwhile)
  int delay_ms = 0, jitter_ms = 0;
  double loss = 0.0;
  std::filesystem::path replay_a, replay_b;  // a site that plays a recording (site --replay)
};

int run_two_site_demo(const DemoOptions& options);

class DemoCommand {
 public:
  explicit DemoCommand(CLI::App& app);  // registers `demo`
  bool parsed() const { return command_->parsed(); }
  int run();

 private:
  CLI::App* command_;
  DemoOptions options_;
  int disconnect_after_ms_ = -1;
};

class SiteCommand {
 public:
  explicit SiteCommand(CLI::App& app);  // registers `site`
  bool parsed() const { return command_->parsed(); }
  int run();

 private:
  CLI::App* command_;
  site::SiteRunOptions options_;
  std::string site_ = "A";
  std::filesystem::path config_;
};

}  // namespace rt::app
