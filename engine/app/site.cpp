// `remotetouch site`: one site of a two-site session (sender and receiver), for a real
// two-machine set-up or as the demo's child. Its options come from --config (site_config.cpp),
// then the flags given on the command line over it.
#include "app/command.h"
#include "app/option_groups.h"
#include "audio/audio_spec.h"
#include "site/site_run.h"

namespace rt::app {
namespace {

using site::SiteRunOptions;
using site::SoundOptions;

class SiteCommand : public Command {
 public:
  CLI::App* add_to(CLI::App& parent) override {
    command_ = parent.add_subcommand("site", "Run one site of a two-site session (sender and receiver) against a peer");
    command_->add_option("--config", config_,
                         "Site config JSON (scene, site, listen, peer, key_file, ..., \"ibr\", \"hand\" and \"touch\" objects); "
                         "flags override it");
    command_->add_option("--peer", options_.peer, "Connect to the other site at HOST:PORT (else listen)");
    command_->add_option("--listen", options_.listen, "Listen on HOST:PORT (port 0: any, printed)")->capture_default_str();
    command_->add_option("--key-file", options_.key_file, "Session key: 64 hex digits, the same at both sites");
    command_->add_option("--transport", options_.transport,
                         "direct: everything over the session; webrtc: the session sets up a WebRTC call that carries "
                         "the portraits as H.264 video and the rest on sealed data channels (the same at both sites)")
        ->check(CLI::IsMember({"direct", "webrtc"}))
        ->capture_default_str();
    command_->add_option("--bitrate-floor-kbps", options_.call.bitrate_floor_kbps,
                         "--transport webrtc: the colour track's lowest bitrate under loss (kbit/s)")
        ->check(CLI::Range(50, 100000))
        ->capture_default_str();
    command_->add_option("--bitrate-ceiling-kbps", options_.call.bitrate_ceiling_kbps,
                         "--transport webrtc: the colour track's highest bitrate on a clean path (kbit/s)")
        ->check(CLI::Range(50, 100000))
        ->capture_default_str();
    command_->add_option("--simulated-loss", options_.call.simulated_loss,
                         "--transport webrtc, tests and the demo: drop this fraction of the outgoing RTP packets "
                         "(GStreamer's netsim)")
        ->check(CLI::Range(0.0, 1.0));
    command_->add_option("--stun", options_.call.stun, "--transport webrtc: a STUN server, stun://HOST:PORT");
    command_->add_option("--turn", options_.call.turn,
                         "--transport webrtc: a TURN relay, turn://USER:PASS@HOST:PORT (coturn)");
    command_->add_flag("--relay-only", options_.call.relay_only,
                       "--transport webrtc: ICE through the --turn relay only (ice-transport-policy relay)");
    command_->add_option("--janus", options_.call.janus,
                         "--transport webrtc: meet the other site in a Janus VideoRoom at ws://HOST:PORT or wss://HOST:PORT instead of "
                         "--peer/--listen (neither site needs a reachable port)");
    command_->add_option("--room", options_.call.room, "--janus: the room's number (the same at both sites)")
        ->check(CLI::Range(uint64_t(1), uint64_t(1) << 52));
    command_->add_option("--room-secret", options_.call.room_secret_file,
                         "--janus: a file holding the room's pin (the first site makes the room with it)");
    command_->add_option("--janus-ca", options_.call.janus_ca_file,
                         "--janus wss://...: the authorities (PEM) Janus's certificate must chain to, for a server with "
                         "its own (default: the system's)");
    command_->add_option("--site", site_, "Which site this is")->check(CLI::IsMember({"A", "B"}))->capture_default_str();
    command_->add_option("--scene", options_.scene, "Scene name under assets/scenes/, or a scene file")->capture_default_str();
    add_run_options(*command_, options_.run, "");
    // Two sites on one machine must not share a folder: the default names the site.
    command_->get_option("--out")->default_str("out/site_A or out/site_B, by --site");
    add_frames_option(*command_, options_.run, 1, "the scene's own count")->description("Scene frames to play");
    options_.run.width = 640;
    options_.run.height = 360;
    add_size_options(*command_, options_.run, "Portrait and display", 16, 4096);
    command_->add_option("--time-scale", options_.time_scale,
                         "Scene seconds per wall-clock second; give both sites the same (a simulated scene plays "
                         "on a shared clock)")
        ->check(CLI::Range(0.01, 10.0))
        ->default_str("1 on a GPU, 0.25 on a CPU Vulkan driver");
    command_->add_option("--resolution-scale", options_.resolution_scale, "Camera resolution scale")
        ->check(CLI::Range(0.01, 1.0))
        ->default_str("the scene's");
    command_->add_option("--connect-timeout", options_.connect_timeout_s, "Seconds to wait for the other site")
        ->check(CLI::Range(0.1, 3600.0))
        ->capture_default_str();
    command_->add_option("--replay", options_.replay,
                         "Replay a recording (remotetouch simulate's format) as this site's cameras and tracker");
    command_->add_option("--site-file", options_.site_file,
                         "This site's description (screen, seat, tracker, cameras) instead of the scene's; cameras "
                         "with \"source\": \"k4a\" run live")
        ->check(CLI::ExistingFile);
    command_->add_option("--motor", options_.motor, "simulated, usb (the Arduino; an error without it) or auto")
        ->check(CLI::IsMember({"simulated", "usb", "auto"}))
        ->capture_default_str();
    auto audio_check = [](const char* option) {
      return [option](const std::string& value) {
        try {
          audio::parse_audio_spec(value, option);
          return std::string();
        } catch (const std::invalid_argument& error) {
          return std::string(error.what());
        }
      };
    };
    command_->add_option("--audio-in", options_.sound.audio_in,
                         "The microphone: simulated (the scene's user and room), pulse (the sound server's default "
                         "input), pulse:DEVICE (one by name, `pactl list short sources`), FILE.wav, or none")
        ->check(audio_check("--audio-in"))
        ->capture_default_str();
    command_->add_option("--audio-out", options_.sound.audio_out,
                         "The loudspeaker: simulated (the room; also written to audio.wav), pulse, pulse:DEVICE "
                         "(`pactl list short sinks`), FILE.wav, or none")
        ->check(audio_check("--audio-out"))
        ->capture_default_str();
    command_->add_flag("--noise-suppression", options_.sound.noise_suppression,
                       "The voice's noise suppression (webrtcdsp), after the echo canceller");
    command_->add_flag("--gain-control", options_.sound.gain_control, "The voice's automatic gain control (webrtcdsp)");
    command_->add_flag("--no-lip-sync", no_lip_sync_,
                       "Play the far voice as it comes instead of holding it to the far portrait (lower sound latency)");
    command_->add_option("--voice-kbps", voice_kbps_, "The voice's Opus bitrate, kbit/s")
        ->check(CLI::Range(6, 128))
        ->capture_default_str();
    command_->add_option("--tracker", options_.tracker,
                         "scene (simulated, or the replay's), or leap[:ws://HOST:PORT/PATH]: the Leap service live")
        ->check([](const std::string& value) {
          try {
            site::leap_tracker_url(value);
            return std::string();
          } catch (const std::invalid_argument& error) {
            return std::string(error.what());
          }
        })
        ->capture_default_str();
    command_->add_option("--display", options_.display,
                         "window (on this machine's display), headless (PNG and MP4 files), both, or auto: a window "
                         "where a display is present (DISPLAY or WAYLAND_DISPLAY set), headless otherwise")
        ->check(CLI::IsMember({"window", "headless", "both", "auto"}))
        ->capture_default_str();
    command_->add_option("--monitor", options_.monitor, "Full screen on this monitor (0 = the first); else windowed")
        ->check(CLI::Range(0, 64));
    command_->add_option("--present-mode", options_.present_mode,
                         "fifo (waits for the screen's refresh), or mailbox where the device offers it (FIFO otherwise)")
        ->check(CLI::IsMember({"fifo", "mailbox"}))
        ->capture_default_str();
    // Not in --help: the demo's children report progress as lines it parses.
    command_->add_flag("--progress-lines", options_.progress_lines)->group("");
    add_inspection_options(*command_, options_.run);
    ibr_ = add_ibr_options(*command_);
    quality_.add_to(*command_);
    hand_ = add_hand_options(*command_);
    touch_ = add_touch_options(*command_);
    return command_;
  }

  int run() override {
    // The config first, then the flags given on the command line over it.
    SiteRunOptions flags = options_;
    auto given = [&](const char* name) { return command_->count(name) > 0; };
    if (!config_.empty()) {
      site::apply_site_config(config_, options_);
      if (given("--peer")) options_.peer = flags.peer;
      if (given("--listen")) options_.listen = flags.listen;
      if (given("--key-file")) options_.key_file = flags.key_file;
      if (given("--transport")) options_.transport = flags.transport;
      if (given("--bitrate-floor-kbps")) options_.call.bitrate_floor_kbps = flags.call.bitrate_floor_kbps;
      if (given("--bitrate-ceiling-kbps")) options_.call.bitrate_ceiling_kbps = flags.call.bitrate_ceiling_kbps;
      if (given("--simulated-loss")) options_.call.simulated_loss = flags.call.simulated_loss;
      if (given("--stun")) options_.call.stun = flags.call.stun;
      if (given("--turn")) options_.call.turn = flags.call.turn;
      if (given("--relay-only")) options_.call.relay_only = flags.call.relay_only;
      if (given("--janus")) options_.call.janus = flags.call.janus;
      if (given("--room")) options_.call.room = flags.call.room;
      if (given("--room-secret")) options_.call.room_secret_file = flags.call.room_secret_file;
      if (given("--janus-ca")) options_.call.janus_ca_file = flags.call.janus_ca_file;
      if (given("--scene")) options_.scene = flags.scene;
      if (given("--time-scale")) options_.time_scale = flags.time_scale;
      if (given("--resolution-scale")) options_.resolution_scale = flags.resolution_scale;
      if (given("--width")) options_.run.width = flags.run.width;
      if (given("--height")) options_.run.height = flags.run.height;
      if (given("--frames")) options_.run.frames = flags.run.frames;
      if (given("--site")) options_.site = site_ == "B" ? Site::B : Site::A;
      if (given("--replay")) options_.replay = flags.replay;
      if (given("--site-file")) options_.site_file = flags.site_file;
      if (given("--motor")) options_.motor = flags.motor;
      if (given("--tracker")) options_.tracker = flags.tracker;
      if (given("--display")) options_.display = flags.display;
      if (given("--monitor")) options_.monitor = flags.monitor;
      if (given("--present-mode")) options_.present_mode = flags.present_mode;
      if (given("--progress-lines")) options_.progress_lines = flags.progress_lines;
    } else {
      options_.site = site_ == "B" ? Site::B : Site::A;
    }
    if (!config_.empty()) {
      for (auto [name, field] : {std::pair{"--audio-in", &SoundOptions::audio_in}, {"--audio-out", &SoundOptions::audio_out}})
        if (given(name)) options_.sound.*field = flags.sound.*field;
      if (given("--noise-suppression")) options_.sound.noise_suppression = flags.sound.noise_suppression;
      if (given("--gain-control")) options_.sound.gain_control = flags.sound.gain_control;
    }
    if (no_lip_sync_) options_.sound.lip_sync = false;
    options_.sound.voice_bitrate_bps = voice_kbps_ * 1000;
    if (given("--frames")) options_.frames_given = true;
    if (options_.run.out.empty()) options_.run.out = std::string("out/site_") + site_name(options_.site);
    options_.ibr.width = options_.run.width;
    options_.ibr.height = options_.run.height;
    options_.quality = quality_.apply(options_.ibr, options_.resolution_scale, given("--resolution-scale"));
    ibr_.apply(options_.ibr);
    hand_.apply(options_.hand);
    touch_.apply(options_.touch);
    return site::run_site(options_);
  }

 private:
  CLI::App* command_ = nullptr;
  SiteRunOptions options_;
  std::string site_ = "A";
  int voice_kbps_ = 28;
  bool no_lip_sync_ = false;
  std::filesystem::path config_;
  IbrOptions ibr_;
  QualityOptions quality_;
  HandOptions hand_;
  TouchOptions touch_;
};

}  // namespace

std::unique_ptr<Command> make_site_command() { return std::make_unique<SiteCommand>(); }

}  // namespace rt::app
