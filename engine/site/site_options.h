#pragma once
// What one site takes from its command line or its --config file (site_config.cpp).
#include <filesystem>
#include <optional>
#include <string>

#include "geometry/site_frames.h"
#include "pipeline/hand_settings.h"
#include "pipeline/ibr_settings.h"
#include "pipeline/run_options.h"
#include "site/site_sound_options.h"
#include "touch/touch_settings.h"

namespace rt::site {

// The WebRTC call's network (--transport webrtc only; media/webrtc_peer.h).
struct CallNetworkOptions {
  int bitrate_floor_kbps = 300, bitrate_ceiling_kbps = 2500;  // the colour track's; depth's ceiling follows
  // Tests and the demo only: GStreamer's netsim drops this fraction of the outgoing RTP. Negative: none.
  double simulated_loss = -1;
  std::string stun;  // stun://HOST:PORT, for the address a NAT shows (media/ice_servers.h)
  std::string turn;  // turn://USER:PASS@HOST:PORT, a relay for networks that let nothing else through
  bool relay_only = false;  // ICE through the TURN relay only (ice-transport-policy relay)
  // Through a Janus VideoRoom instead of a session between the sites (media/janus_link.h): its
  // WebSocket URL, the room's number, a file holding its pin, and for wss:// a file of the
  // authorities its certificate is checked against (empty: the system's).
  std::string janus;
  uint64_t room = 0;
  std::filesystem::path room_secret_file, janus_ca_file;
  bool any_given() const {
    return simulated_loss >= 0 || !stun.empty() || !turn.empty() || relay_only || bitrate_floor_kbps != 300 ||
           bitrate_ceiling_kbps != 2500 || !janus.empty() || room != 0 || !room_secret_file.empty() ||
           !janus_ca_file.empty();
  }
};

struct SiteRunOptions {
  pipeline::RunOptions run;             // out (this site's folder), device, validation, width x height, frames
  bool frames_given = false;  // else the scene's own frame count
  std::string scene = "clap";
  Site site = Site::A;
  std::string listen = "127.0.0.1:0";  // listener: where to listen (port 0: any; printed as "listening on PORT")
  std::string peer;                    // connector: the listener's HOST:PORT; empty = be the listener
  std::filesystem::path key_file;      // 64 hex digits; both sites need the same
  // How portraits and messages travel: "direct" (everything over the session) or "webrtc" (the
  // session sets up a WebRTC call, media/webrtc_link.h). Both sites need the same.
  std::string transport = "direct";
  CallNetworkOptions call;
  double time_scale = 0.0;             // scene seconds per wall-clock second; 0 = by the device (site_run.cpp)
  double resolution_scale = 0.0;       // of the cameras; 0 = the scene's own
  bool write_truth = true;             // this site's user seen from the remote eye, over the background
  double connect_timeout_s = 60.0;
  // For a parent that reads stdout (the demo): "progress N TOTAL" lines and no closing table.
  bool progress_lines = false;
  double linger_s = 1.5;  // after the last capture, how long without a new portrait ends the display
  // This site's devices: empty = simulated from the scene; else a recording (sim/recording.h) to
  // replay: its cameras, frames, times and tracker replace the scene's at this site.
  std::filesystem::path replay;
  // This site's description instead of the scene's (empty: the scene's); cameras whose source is
  // "k4a" run live (camera/site_camera_sources.h).
  std::filesystem::path site_file;
  std::string motor = "auto";  // simulated | usb | auto (the Arduino on USB when attached)
  // The hand tracker: "scene" (simulated from the scene, or the replay's tracker.jsonl), or
  // "leap" / "leap:ws://HOST:PORT/PATH", the Leap service live (devices/tracker/leap_service.h).
  std::string tracker = "scene";
  // Where the composite goes: "window" (a window on this machine's display), "headless" (PNG and
  // MP4 files), "both", or "auto": a window where a display is present, headless otherwise.
  std::string display = "auto";
  int monitor = -1;                    // full screen on this monitor; -1 = windowed
  std::string present_mode = "fifo";   // fifo | mailbox (where the device offers it)
  pipeline::IbrSettings ibr;            // the sender's image-based model (its width and height are the display's)
  nlohmann::json quality;               // what --quality or --budget-ms chose, for metrics; null: neither
  pipeline::HandRendererOptions hand;   // the receiver's geometry hand
  TouchSettings touch;                  // contact prediction and the motor's latency
  SoundOptions sound;                   // microphone, loudspeaker, the voice's knobs (site_sound.h)
};

// Fills the fields a --config JSON names (scene, site, listen, peer, key_file, transport, time_scale,
// resolution_scale, width, height, frames, replay, site_file, motor, tracker, and the objects "ibr", "hand" and
// "touch" of the knobs in pipeline/ibr_settings.h, hand_settings.h and touch/touch_settings.h,
// e.g. "ibr": {"refine": 9, "best_views": 4}); a file path (key_file, replay, site_file, room_secret, janus_ca) is relative to the config's folder.
// Throws naming the file and field.
// The Leap service's URL that a --tracker value names, or none for "scene". Throws
// std::invalid_argument saying what is wrong with any other value.
std::optional<std::string> leap_tracker_url(const std::string& tracker);

enum class DisplayMode { Window, Headless, Both };
// "auto" is a window where a display is present (display_present: DISPLAY or WAYLAND_DISPLAY
// set). Throws std::invalid_argument naming the choices for any other value.
DisplayMode parse_display_mode(const std::string& display, bool display_present);
bool display_present();

void apply_site_config(const std::filesystem::path& config, SiteRunOptions& options);

}  // namespace rt::site
