#pragma once
// `remotetouch demo`'s run (the command is demo.cpp): both sites of a scene as two processes
// (`remotetouch site`, site.cpp) over loopback, with a progress bar, merged events, metrics and a
// summary table.
#include <optional>

#include "app/options.h"
#include "pipeline/hand_settings.h"
#include "pipeline/ibr_settings.h"
#include "touch/touch_settings.h"

namespace rt::app {

struct DemoOptions {
  RunOptions run;
  bool frames_given = false;
  std::string scene = "clap";
  double time_scale = 0.0;  // 0: the sites choose by the device (site --time-scale)
  double resolution_scale = 0.0;  // 0 = the scene's own
  // Faults on the link (through net::FaultProxy; none by default).
  std::optional<int> disconnect_after_ms;
  int outage_ms = 0;  // after the cut, the link stays silent this long (reconnects fail meanwhile)
  int delay_ms = 0, jitter_ms = 0;
  double loss = 0.0;
  // direct: everything over the session; webrtc: a WebRTC call set up over it (site --transport).
  std::string transport = "direct";
  // webrtc only: each site's outgoing RTP loses this fraction of its packets (site --simulated-loss,
  // GStreamer's netsim); negative: no simulated network.
  double packet_loss = -1;
  std::filesystem::path replay_a, replay_b;  // a site that plays a recording (site --replay)
  // Each site's window (site --display): the demo's report reads the frames, so a window always
  // comes with them (both); auto is a window where a display is present.
  std::string display = "auto";
  std::string present_mode = "fifo";
  std::string sound = "simulated";  // both sites' microphone and loudspeaker: simulated or none
  bool noise_suppression = false, gain_control = false, no_lip_sync = false;
  pipeline::IbrSettings ibr;                 // both sites' image-based model (forwarded to each)
  nlohmann::json quality;                    // what --quality or --budget-ms chose; null: neither
  std::vector<std::string> quality_arguments;  // the same choice for each site, for its metrics
  pipeline::HandRendererOptions hand;        // both sites' geometry hand
  TouchSettings touch;                       // both sites' contact prediction and motor latency
};

int run_two_site_demo(const DemoOptions& options);

}  // namespace rt::app
