#include "site/site_run.h"

#include <algorithm>
#include <csignal>
#include <cmath>
#include <cstdio>
#include <deque>
#include <fstream>
#include <iostream>
#include <numbers>
#include <nlohmann/json.hpp>
#include <optional>
#include <thread>

#include "display/glfw_window.h"
#include "media/sound_into_video.h"
#include "media/touch_sound.h"
#include "media/ice_servers.h"
#include "media/janus_link.h"
#include "media/webrtc_link.h"
#include "net/session.h"
#include "pipeline/demo_layers.h"
#include "pipeline/gpu_session.h"
#include "site/closing_table.h"
#include "site/receiver.h"
#include "site/sender.h"
#include "site/site_common.h"
#include "site/site_metrics.h"
#include "site/site_motor.h"
#include "site/site_sound.h"
#include "session/output_folder_lock.h"
#include "time/monotonic_clock.h"
#include "motor/simulated_motor.h"
#include "touch/scene_contact.h"
#include "touch/site_touch_loop.h"

namespace rt::site {
namespace {

// SIGINT or SIGTERM asks the site to stop: the handler only notes which; the monitor loop ends
// the stages, and the site writes its metrics as after a normal end.
volatile std::sig_atomic_t g_stop_signal = 0;
extern "C" void note_stop_signal(int signal) { g_stop_signal = signal; }

void install_stop_handlers() {
  struct sigaction action {};
  action.sa_handler = note_stop_signal;
  sigemptyset(&action.sa_mask);
  for (const int signal : {SIGINT, SIGTERM}) sigaction(signal, &action, nullptr);
}

}  // namespace

bool stop_signal_received() { return g_stop_signal != 0; }

namespace {

const char* signal_name(int signal) { return signal == SIGINT ? "SIGINT" : signal == SIGTERM ? "SIGTERM" : "a signal"; }

// --profile: each graph's passes with their median GPU time, as metrics.json has them.
void print_profile(const std::string& site, const nlohmann::json& gpu_ms) {
  auto row = [](const std::string& name, double ms) {
    char line[96];
    std::snprintf(line, sizeof(line), "  %-28s %9.3f\n", name.c_str(), ms);
    std::cout << line;
  };
  for (const auto& [stage, passes] : gpu_ms.items()) {
    std::cout << "site " << site << ", " << stage << ": GPU ms per pass (median over the run)\n";
    for (const auto& [pass, ms] : passes.items())
      if (pass != "total" && ms.is_number()) row(pass, ms.get<double>());
    if (passes.contains("total") && passes["total"].is_number()) row("total", passes["total"].get<double>());
  }
}

net::SessionOptions session_options(const SiteRunOptions& options) {
  net::SessionOptions net_options;
  net_options.key = net::load_session_key_file(options.key_file);
  net_options.name = std::string("site ") + site_name(options.site);
  net_options.decode.portrait_width = options.run.width;
  net_options.decode.portrait_height = options.run.height;
  if (options.peer.empty()) {
    net_options.role = net::Role::Listener;
    // Port 0 (any free port) is fine for a listener, which parse_host_port refuses for a peer.
    const size_t colon = options.listen.rfind(':');
    if (colon != std::string::npos && options.listen.substr(colon) == ":0") {
      net_options.host = options.listen.substr(0, colon);
      net_options.port = 0;
    } else {
      std::tie(net_options.host, net_options.port) = net::parse_host_port(options.listen);
    }
  } else {
    net_options.role = net::Role::Connector;
    std::tie(net_options.host, net_options.port) = net::parse_host_port(options.peer);
  }
  return net_options;
}

// The link through a Janus room: the room's number and pin from the options (the pin's file read
// here, its size bounded), the site key's handshake roles by site (A connects, B listens: in a
// room neither does either).
std::unique_ptr<net::Transport> make_janus_link(const SiteRunOptions& options, net::SessionOptions session,
                                                const media::WebRtcPeerOptions& call) {
  if (!options.peer.empty()) throw std::invalid_argument("--janus and --peer: through Janus neither site connects to the other");
  if (options.call.room == 0) throw std::invalid_argument("--janus needs --room NUMBER (the same at both sites)");
  media::JanusRoomOptions room;
  room.url = options.call.janus;
  room.room = options.call.room;
  room.display = session.name;
  if (!options.call.janus_ca_file.empty()) {
    if (!media::parse_janus_url(room.url).tls)
      throw std::invalid_argument("--janus-ca names the authorities of a wss:// Janus; " + room.url + " is not one");
    room.ca_file = options.call.janus_ca_file.string();
  }
  if (!options.call.room_secret_file.empty()) {
    std::ifstream in(options.call.room_secret_file, std::ios::binary);
    if (!in) throw std::invalid_argument("--room-secret " + options.call.room_secret_file.string() + ": cannot be read");
    std::string pin(257, '\0');
    in.read(pin.data(), std::streamsize(pin.size()));
    pin.resize(size_t(in.gcount()));
    while (!pin.empty() && (pin.back() == '\n' || pin.back() == '\r' || pin.back() == ' ')) pin.pop_back();
    if (pin.empty() || pin.size() > 256)
      throw std::invalid_argument("--room-secret " + options.call.room_secret_file.string() + ": a pin of 1 to 256 bytes, not " +
                                  (pin.empty() ? std::string("an empty file") : std::string("more")));
    room.pin = pin;
  }
  session.role = options.site == Site::A ? net::Role::Connector : net::Role::Listener;
  // Janus does not take loopback for media: ICE gathers on every interface but loopback.
  media::WebRtcPeerOptions relayed = call;
  relayed.local_addresses.clear();
  return std::make_unique<media::JanusLink>(session, room, relayed);
}

// The site: its sender and receiver, the touch loop and the motor, the link, and the threads
// that run them until the scene ends.
class SiteRun {
 public:
  // `started_us`: when the site started; the connect timeout counts from it.
  SiteRun(const SiteRunOptions& options, uint64_t started_us);
  int run();

 private:
  void on_message(const net::Message& message);
  void on_touch(const TouchEvent& event);
  // The touch loop's cue to pulse the motor (ahead of a predicted contact, or at a detected touch)
  // or to cancel a predicted pulse whose touch did not come (touch/touch_loop.h).
  // A pulse is one step of the gesture's pattern (touch/gesture.h); the first starts it.
  void on_motor(MotorCue cue, const MotorStep& step, Gesture gesture);
  // The touch's sound, the gesture's own: at the predicted contact for a pulse given ahead of it,
  // else now; from where this site's hand nearest the glass is, as the seat hears it.
  void play_touch_sound(uint64_t command_us, bool predicted, Gesture gesture);
  // audio.wav into site.mp4, where both were written: the video runs at the scene's pace on the
  // wall's clock, as the sound does.
  void put_sound_into_video();
  // When the user claps each of the scene's sound-against-picture markers: the capture time of
  // the first camera frame that shows its flash, so that the clap and the flash are one instant.
  std::vector<uint64_t> marker_claps_us() const;
  // The touch-to-motor latencies, once a touch has both its start and its pulse.
  void note_touch_to_motor();
  // Each true contact of the scene against the vibrations felt, where the truth is known: this
  // site's inputs simulated from the scene (the other site is taken to play the same scene) and
  // the motor simulated.
  nlohmann::json contact_to_vibration() const;
  // Connection changes into the event log and progress lines for the demo's parent, until the
  // display ends.
  void monitor(const std::atomic<bool>& display_finished);
  // Polls the window's events (main thread); true once Esc or the window's close asked to quit.
  bool window_quit();
  // Stopped (a signal or the window) before the other site connected: metrics.json says so.
  int stop_before_connected(const std::string& by, int exit_status);

  pipeline::GpuSession gpu_;
  DisplayMode display_mode_;
  std::unique_ptr<display::GlfwWindow> window_;  // made, polled and closed on this (the main) thread
  std::unique_ptr<SiteCapture> capture_;
  session::EventLog events_;
  SiteCommon common_;
  SiteMotor motor_;  // used by the touch loop's thread only (usb_motor.h)
  std::unique_ptr<SiteTouchLoop> touch_;
  std::unique_ptr<Sender> sender_;
  std::unique_ptr<Receiver> receiver_;
  // Declared after the sender and the receiver, so destroyed before them: its thread calls them.
  std::unique_ptr<net::Transport> net_;
  // After the transport: its thread sends and takes voice frames, so it stops first.
  std::unique_ptr<SiteSound> sound_;
  std::mutex skeleton_mutex_;
  std::deque<std::pair<uint64_t, uint64_t>> remote_capture_of_stamp_;  // (stamp here, sender's capture) µs
  session::LatencyStats touch_to_motor_, detect_to_motor_;
  // The touch loop's thread alone: the newest touch start's (met, detected) times and the newest
  // pulse's command time, until the two are paired.
  std::optional<std::pair<uint64_t, uint64_t>> unpaired_start_us_;
  std::optional<uint64_t> unpaired_pulse_us_;
  uint64_t touch_sound_id_ = 0;  // the last touch's sound, withdrawn if its prediction is
  uint64_t started_us_ = 0;
  std::string stopped_by_;  // SIGINT, SIGTERM, window or peer; empty: the scene ended
  std::atomic<bool> told_transport_mismatch_{false};
};

SiteRun::SiteRun(const SiteRunOptions& options, uint64_t started_us)
    : gpu_((std::filesystem::create_directories(options.run.out), options.run)),
      events_(options.run.out / "events.jsonl", site_name(options.site)),
      started_us_(started_us) {
  common_.options = options;
  common_.name = site_name(options.site);
  if (!(options.time_scale >= 0) || !std::isfinite(options.time_scale)) throw std::invalid_argument("--time-scale must be > 0");
  if (options.time_scale == 0) {
    // A CPU driver renders a site far slower than the scene plays: in real time it would
    // show few of the scene's frames. A quarter of real time shows most of them.
    const bool cpu = gpu_.context().is_cpu_device();
    common_.options.time_scale = cpu ? 0.25 : 1.0;
    std::cerr << "site " << common_.name << ": time scale " << common_.options.time_scale
              << (cpu ? " (a quarter of real time: " + gpu_.context().device_name() + " is a CPU Vulkan driver)"
                      : " (real time)")
              << "; --time-scale sets it\n";
  }
  common_.remote = other_site(options.site);
  common_.scene = sim::load_scene(sim::resolve_scene(options.scene));
  if (!options.site_file.empty() && !options.replay.empty())
    throw std::invalid_argument("--site-file and --replay both say where this site's cameras are: give one (a "
                                "replay's folder holds its own site.json)");
  if (!options.site_file.empty()) {
    // This site as its own site file describes it (its screen, seat, tracker and cameras, which
    // may be live devices); the scene still gives the other site and the simulated users.
    sim::SiteSetup& setup = common_.scene.sites[options.site == Site::A ? 0 : 1];
    setup.site = sim::load_site(options.site_file);
    setup.site_file = options.site_file;
  }
  common_.width = options.run.width;
  common_.height = options.run.height;
  common_.out = options.run.out;
  common_.context = &gpu_.context();
  display_mode_ = parse_display_mode(options.display, display_present());
  if (display_mode_ != DisplayMode::Headless) {
    window_ = std::make_unique<display::GlfwWindow>(display::WindowOptions{
        .title = "RemoteTouch site " + common_.name, .width = options.run.width, .height = options.run.height,
        .monitor = options.monitor});
    common_.window = window_.get();
    std::cerr << "site " << common_.name << ": window: " << window_->description() << "\n";
  }
  common_.write_frames = display_mode_ != DisplayMode::Window;
  capture_ = std::make_unique<SiteCapture>(gpu_, options.run.capture_frame, common_.name);
  common_.capture = capture_.get();
  common_.events = &events_;
  common_.background = pipeline::make_demo_layers(common_.width, common_.height).background;
  if (options.frames_given) common_.scene.frame_count = options.run.frames;
  if (options.resolution_scale > 0) common_.scene.resolution_scale = options.resolution_scale;
  std::filesystem::create_directories(common_.out / "frames");
  if (options.write_truth) std::filesystem::create_directories(common_.out / "truth");

  motor_ = open_site_motor(
      parse_motor_mode(options.motor),
      [this](const std::string& line) {
        std::cerr << "site " << common_.name << ": motor: " << line << "\n";
        events_.write("motor_log", monotonic_now_us(), {{"line", line}});
      },
      std::chrono::microseconds(std::llround(options.touch.motor_latency_ms * 1000.0)));
  std::cerr << "site " << common_.name << ": motor: " << motor_.description << "\n";
  events_.write("motor", monotonic_now_us(), {{"motor", motor_.description}});

  touch_ = std::make_unique<SiteTouchLoop>(
      options.touch, common_.options.time_scale, [this](const TouchEvent& event) { on_touch(event); },
      [this](MotorCue cue, uint64_t, const MotorStep& step, Gesture gesture) { on_motor(cue, step, gesture); });

  net::SessionOptions net_options = session_options(options);
  net_options.log = [this](const std::string& line) {
    std::cerr << line << "\n";
    events_.write("net_log", monotonic_now_us(), {{"line", line}});
  };
  if (options.transport == "webrtc") {
    media::WebRtcPeerOptions call;
    call.width = options.run.width;
    call.height = options.run.height;
    call.color_floor_kbps = options.call.bitrate_floor_kbps;
    call.color_ceiling_kbps = options.call.bitrate_ceiling_kbps;
    call.color_kbps = std::clamp(call.color_kbps, call.color_floor_kbps, call.color_ceiling_kbps);
    call.simulated_loss = options.call.simulated_loss;
    call.stun_server = options.call.stun.empty() ? "" : media::parse_stun_url(options.call.stun);
    call.turn_server = options.call.turn.empty() ? "" : media::parse_turn_url(options.call.turn);
    call.relay_only = options.call.relay_only;
    if (!options.call.janus.empty()) {
      net_ = make_janus_link(options, net_options, call);
      std::cerr << "site " << common_.name << ": transport webrtc through Janus at " << options.call.janus << ", room "
                << options.call.room << " (portraits as H.264 video)\n";
    } else {
      if (options.call.room != 0 || !options.call.room_secret_file.empty() || !options.call.janus_ca_file.empty())
        throw std::invalid_argument("--room, --room-secret and --janus-ca name a Janus room: they need --janus");
      net_ = std::make_unique<media::WebRtcLink>(net_options, call);
      std::cerr << "site " << common_.name << ": transport webrtc (the session sets up the call; portraits as H.264 video)\n";
    }
  } else if (options.transport == "direct") {
    if (options.call.any_given())
      throw std::invalid_argument("--stun, --turn, --relay-only, --simulated-loss and the bitrate's floor and ceiling "
                                  "are the WebRTC call's: they need --transport webrtc");
    net_ = std::make_unique<net::Session>(net_options);
  } else {
    throw std::invalid_argument("--transport must be direct or webrtc, not '" + options.transport + "'");
  }
  common_.net = net_.get();
  common_.eye_search_deadline_us = started_us_ + uint64_t(options.connect_timeout_s * 1e6);
  // The sender first: a replay replaces the scene's site, which the receiver then shows.
  sender_ = std::make_unique<Sender>(common_, *touch_);
  receiver_ = std::make_unique<Receiver>(common_);
  common_.sender_graph = &sender_->ibr_graph();
  net_->set_handler([this](const net::Message& message) { on_message(message); });
  sound_ = std::make_unique<SiteSound>(options.sound, options.site, common_.scene.effects, common_.out, *net_,
                                       [this](const std::string& line) {
                                         std::cerr << "site " << common_.name << ": sound: " << line << "\n";
                                         events_.write("sound_log", monotonic_now_us(), {{"line", line}});
                                       });
  std::cerr << "site " << common_.name << ": sound: " << sound_->description() << "\n";
  events_.write("sound", monotonic_now_us(), {{"sound", sound_->description()}});
}

std::vector<uint64_t> SiteRun::marker_claps_us() const {
  std::vector<uint64_t> at_us;
  if (!common_.scene.effects.av_marker) return at_us;
  for (const double t_s : common_.scene.effects.av_marker->times_s) {
    const double first_frame = std::ceil(t_s * common_.scene.fps - 1e-9);
    at_us.push_back(common_.wall_us_at_scene_time(first_frame / common_.scene.fps));
  }
  return at_us;
}

void SiteRun::on_message(const net::Message& message) {
  const uint64_t now = monotonic_now_us();
  const Site here = common_.options.site;
  if (const auto* voice = std::get_if<net::VoiceMessage>(&message)) {
    if (sound_) sound_->receive(*voice);
  } else if (const auto* eye = std::get_if<net::EyeMessage>(&message)) {
    if (eye->valid) sender_->set_remote_eye(map_point(common_.remote, here, eye->eye));
  } else if (const auto* skeleton = std::get_if<net::SkeletonMessage>(&message)) {
    // The hands' capture times on the other machine's clock come onto this one by the link's
    // least delay (touch/remote_clock.h): its delay is not the tracker losing the hand, and the
    // contact's prediction needs their spacing. The sender's own time is kept aside for the
    // touch-to-motor latency (the demo's two sites share one clock).
    std::vector<HandSkeleton> hands;
    for (const auto& hand : skeleton->hands) hands.push_back(map_skeleton(common_.remote, here, hand));
    const uint64_t captured_there_us = skeleton->hands.empty() ? skeleton->timestamp_us : skeleton->hands.front().timestamp_us;
    const uint64_t captured_here_us = touch_->set_remote_hands(std::move(hands), captured_there_us, now);
    {
      std::lock_guard lock(skeleton_mutex_);
      remote_capture_of_stamp_.emplace_back(captured_here_us, captured_there_us);
      while (remote_capture_of_stamp_.size() > 200) remote_capture_of_stamp_.pop_front();
    }
    receiver_->on_skeleton(*skeleton);
  } else if (const auto* portrait = std::get_if<net::PortraitMessage>(&message)) {
    receiver_->on_portrait(*portrait, now);
  } else if (const auto* touch = std::get_if<net::TouchEventMessage>(&message)) {
    events_.write(touch->kind == net::TouchEventMessage::Kind::Start ? "remote_touch_start" : "remote_touch_end", now,
                  {{"detected_by", touch->site == 0 ? "A" : "B"}, {"gesture", gesture_name(Gesture(touch->gesture))}});
  } else if (std::holds_alternative<net::SignalMessage>(message) && !told_transport_mismatch_.exchange(true)) {
    // Only a direct session hands signals up: the other site is calling over WebRTC.
    std::cerr << "site " << common_.name << ": the other site runs --transport webrtc and this one "
              << common_.options.transport << ": give both the same\n";
    events_.write("transport_mismatch", now, {{"here", common_.options.transport}});
  }
}

void SiteRun::on_touch(const TouchEvent& event) {
  const bool start = event.kind == TouchEvent::Kind::Start;
  events_.write(start ? "touch_start" : "touch_end", event.timestamp_us,
                {{"overlap_cm2", event.overlap_area_m2 * 1e4},
                 {"gesture", gesture_name(event.gesture)},
                 {"local_capture_us", event.local_capture_us},
                 {"remote_capture_us", event.remote_capture_us}});
  net::TouchEventMessage message;
  message.timestamp_us = event.timestamp_us;
  message.kind = start ? net::TouchEventMessage::Kind::Start : net::TouchEventMessage::Kind::End;
  message.site = common_.options.site == Site::A ? 0 : 1;
  message.gesture = uint8_t(event.gesture);
  net_->send(message);
  if (!start) {
    unpaired_start_us_.reset();
    unpaired_pulse_us_.reset();
    return;
  }
  // The hands met when the later of the two skeletons that showed it was captured.
  uint64_t remote_capture_us = 0;
  {
    std::lock_guard lock(skeleton_mutex_);
    for (const auto& [stamp, capture] : remote_capture_of_stamp_)
      if (stamp == event.remote_capture_us) remote_capture_us = capture;
  }
  const uint64_t met_us = remote_capture_us ? std::max(event.local_capture_us, remote_capture_us) : 0;
  unpaired_start_us_ = {met_us, event.timestamp_us};
  note_touch_to_motor();
}

void SiteRun::on_motor(MotorCue cue, const MotorStep& step, Gesture gesture) {
  const uint64_t command_us = monotonic_now_us();
  if (cue == MotorCue::Cancel) {
    const motor::MotorStatus status = motor_.motor->stop();
    events_.write(status ? "motor_cancel" : "motor_error", command_us,
                  status ? nlohmann::json::object() : nlohmann::json{{"error", status.error()}});
    unpaired_pulse_us_.reset();
    sound_->cancel_touch_sound(touch_sound_id_);
    return;
  }
  if (step.after.count() == 0) play_touch_sound(command_us, !unpaired_start_us_.has_value(), gesture);
  const motor::MotorStatus status = motor_.motor->pulse(step.duration, step.strength);
  if (!status) {
    events_.write("motor_error", command_us, {{"error", status.error()}});
    return;
  }
  if (step.after.count() > 0) {  // a later step of the pattern: the touch's pulse was its first
    events_.write("motor_step", command_us,
                  {{"duration_ms", step.duration.count()}, {"strength", step.strength}, {"gesture", gesture_name(gesture)}});
    return;
  }
  // A predicted contact's pulse usually leaves before the detector sees the touch.
  events_.write("motor_pulse", command_us,
                {{"duration_ms", step.duration.count()},
                 {"strength", step.strength},
                 {"gesture", gesture_name(gesture)},
                 {"steps", motor_pattern(gesture).size()},
                 {"ahead_of_detection", !unpaired_start_us_.has_value()}});
  unpaired_pulse_us_ = command_us;
  note_touch_to_motor();
}

void SiteRun::play_touch_sound(uint64_t command_us, bool predicted, Gesture gesture) {
  const media::TouchSound sound = gesture == Gesture::Fist     ? media::TouchSound::FistBump
                                  : gesture == Gesture::Finger ? media::TouchSound::FingerTap
                                                               : media::TouchSound::Clap;
  const std::vector<HandSkeleton> hands = touch_->loop().local_hands();
  const HandSkeleton* hand = hand_nearest_screen(hands);
  const Eigen::Vector3d on_glass =
      hand ? Eigen::Vector3d(hand->palm.x(), hand->palm.y(), 0.0) : Eigen::Vector3d::Constant(std::nan(""));
  const Eigen::Vector3d& head = common_.scene.at(common_.options.site).site.seat.head_centre_m;
  const uint64_t latency_us = uint64_t(std::llround(common_.options.touch.motor_latency_ms * 1000.0));
  const uint64_t onset_us = predicted ? command_us + latency_us : command_us;
  const media::StereoPlacement placement = media::place_between_loudspeakers(on_glass, head);
  touch_sound_id_ = sound_->play_touch_sound(sound, onset_us, placement);
  if (touch_sound_id_)
    events_.write("touch_sound", command_us,
                  {{"sound", media::touch_sound_name(sound)},
                   {"onset_us", onset_us},
                   {"azimuth_deg", placement.azimuth_rad * 180.0 / std::numbers::pi}});
}

void SiteRun::put_sound_into_video() {
  const std::filesystem::path video = common_.out / "site.mp4", sound = sound_->heard_path();
  const uint64_t video_start_us = receiver_->first_video_frame_us(), sound_start_us = sound_->heard_start_us();
  if (sound.empty() || !video_start_us || !sound_start_us || !std::filesystem::exists(video)) return;
  const int64_t offset_us = int64_t(sound_start_us) - int64_t(video_start_us);
  const std::string error = media::put_sound_into_video(video, sound, offset_us);
  if (!error.empty()) std::cerr << "site " << common_.name << ": site.mp4 stays silent: " << error << "\n";
  events_.write("sound_in_video", monotonic_now_us(),
                {{"muxed", error.empty()}, {"sound_minus_video_ms", double(offset_us) / 1000.0}, {"error", error}});
}

void SiteRun::note_touch_to_motor() {
  if (!unpaired_start_us_ || !unpaired_pulse_us_) return;
  const auto [met_us, detected_us] = *unpaired_start_us_;
  const uint64_t command_us = *unpaired_pulse_us_;
  const double met_to_motor_ms = met_us ? double(int64_t(command_us) - int64_t(met_us)) / 1000.0 : NAN;
  touch_to_motor_.add(met_to_motor_ms);
  detect_to_motor_.add(double(int64_t(command_us) - int64_t(detected_us)) / 1000.0);
  events_.write("touch_to_motor", command_us,
                {{"touch_to_motor_ms", std::isfinite(met_to_motor_ms) ? nlohmann::json(met_to_motor_ms) : nlohmann::json()}});
  unpaired_start_us_.reset();
  unpaired_pulse_us_.reset();
}

nlohmann::json SiteRun::contact_to_vibration() const {
  const auto* simulated = dynamic_cast<const motor::SimulatedMotor*>(motor_.motor.get());
  const SiteRunOptions& options = common_.options;
  if (!simulated || !sender_->simulated() || options.tracker != "scene") return nullptr;
  std::vector<uint64_t> contacts_us;
  for (const double t : true_contact_times_s(common_.scene))
    if (t <= common_.scene.duration_s()) contacts_us.push_back(common_.wall_us_at_scene_time(t));
  nlohmann::json out = contact_to_vibration_json(contacts_us, simulated->felt_pulse_starts(),
                                                 uint64_t(500'000 / std::min(options.time_scale, 1.0)));
  out["note"] = "felt = the simulated motor's command + its latency; contact = the scene's true palms meeting (each "
                "within 1 mm of resting on the glass, overlapping), on this site's clock; error = felt - contact";
  return out;
}

bool SiteRun::window_quit() {
  if (!window_) return false;
  window_->poll();
  return window_->quit_requested();
}

void SiteRun::monitor(const std::atomic<bool>& display_finished) {
  net::ConnectionState state = net::ConnectionState::Connected;
  uint64_t last_progress = 0;
  const uint64_t frames = common_.scene.frame_count;
  bool stop_noted = false;
  uint64_t last_hold_us = 0;
  while (!display_finished) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    const uint64_t now = monotonic_now_us();
    // The far voice waits for the far portrait: lips and words together.
    if (common_.options.sound.lip_sync && now - last_hold_us >= 500'000) {
      last_hold_us = now;
      sound_->hold_voice_to(receiver_->recent_portrait_latency_ms());
    }
    const bool quit = window_quit();
    const net::ConnectionStatus status = net_->status();
    // The other site ending its session (its scene over, or stopped) ends this one too: there is
    // nobody left to send to or to show.
    const bool peer_ended = status.state == net::ConnectionState::Ended;
    if (peer_ended && !g_stop_signal && !quit && now > common_.end_us && !stop_noted) {
      // Both scenes are over: the other site finished first, and this one stops waiting for more.
      stop_noted = true;
      common_.stopping = true;
      common_.sender_done = true;
      sender_->stop();
      receiver_->stop();
    }
    if ((g_stop_signal || quit || peer_ended) && !stop_noted) {
      stop_noted = true;
      stopped_by_ = g_stop_signal ? signal_name(g_stop_signal) : quit ? "window" : "peer";
      const std::string by = g_stop_signal ? stopped_by_
                             : quit        ? std::string("the window (Esc)")
                                           : "the other site ended the session";
      std::cerr << "site " << common_.name << ": " << by << ": stopping\n";
      events_.write("stopped", now, {{"by", stopped_by_}});
      common_.stopping = true;
      common_.sender_done = true;
      sender_->stop();
      receiver_->stop();
    }
    if (status.state != state) {
      const char* phase = now > common_.end_us ? "shutdown" : "run";
      if (status.state == net::ConnectionState::Connected)
        events_.write("connection_restored", now, {{"peer", status.peer}, {"phase", phase}});
      else if (state == net::ConnectionState::Connected)
        events_.write("connection_lost", now,
                      {{"state", net::connection_state_name(status.state)}, {"reason", status.reason}, {"phase", phase}});
      state = status.state;
    }
    const uint64_t frame = std::min<uint64_t>(sender_->last_scene_frame() + 1, frames);
    if (frame != last_progress && common_.options.progress_lines) {
      std::cout << "progress " << frame << " " << frames << std::endl;
    } else if (frame != last_progress && frame * 10 / frames != last_progress * 10 / frames) {
      // A person reads a line per tenth of the scene, not one per frame.
      std::cerr << "site " << common_.name << ": scene frame " << frame << " of " << frames << "\n";
    }
    last_progress = frame;
  }
}

int SiteRun::stop_before_connected(const std::string& by, int exit_status) {
  std::cerr << "site " << common_.name << ": " << (by == "window" ? "window closed" : by) << " before the other site connected\n";
  events_.write("stopped", monotonic_now_us(), {{"by", by}, {"phase", "waiting_for_peer"}});
  nlohmann::json m = site_metrics(common_, 0.0);
  m["stopped_by"] = by;
  m["phase"] = "waiting_for_peer";
  m["connected"] = false;
  net_->stop();
  std::ofstream(common_.out / "metrics.json") << m.dump(2) << "\n";
  return exit_status;
}

int SiteRun::run() {
  const SiteRunOptions& options = common_.options;
  net_->start();
  if (options.peer.empty()) std::cout << "listening on " << net_->local_port() << std::endl;
  events_.write("waiting_for_peer", monotonic_now_us(), {{"role", options.peer.empty() ? "listener" : "connector"}});
  // Waited for in slices, so that a stop signal ends the wait too. The timeout counts from the
  // site's start: what it does before listening or connecting is part of the user's wait.
  const uint64_t give_up_us = started_us_ + uint64_t(options.connect_timeout_s * 1e6);
  // A refusal is no reason to give up before the connect timeout: whoever refused may be a
  // stranger's listener on the address, the other site's previous release, a key being replaced
  // there, or a listener under a flood. The session tries again with back-off; each failed attempt
  // is told here with its reason, so that a wrong key is plain long before the timeout.
  const bool connector = !options.peer.empty();
  uint64_t failures_told = 0;
  auto tell_failures = [&] {
    const uint64_t failures = net_->counters().handshakes_refused;
    if (!connector || failures == failures_told) return;
    const uint64_t more = failures - failures_told - 1;
    failures_told = failures;
    const net::ConnectionStatus status = net_->status();
    const uint64_t now = monotonic_now_us();
    const double left_s = now < give_up_us ? double(give_up_us - now) * 1e-6 : 0.0;
    char left[32];
    std::snprintf(left, sizeof left, "%.1f", left_s);
    std::cerr << "site " << common_.name << ": "
              << (status.state == net::ConnectionState::Refused ? "the other site refused the connection ("
                                                                  : "a connection attempt failed (")
              << status.reason << ")" << (more ? " (and " + std::to_string(more) + " more attempts)" : "")
              << "; trying again for up to " << left << " s\n";
  };
  bool connected = false;
  while (!(connected = net_->wait_connected(std::chrono::milliseconds(100))) && !g_stop_signal && !window_quit() &&
         monotonic_now_us() < give_up_us) {
    tell_failures();
  }
  if (!connected && window_quit()) return stop_before_connected("window", 0);
  if (!connected && g_stop_signal) return stop_before_connected(signal_name(g_stop_signal), 128 + g_stop_signal);
  if (!connected) {
    const net::ConnectionStatus status = net_->status();
    events_.write("connect_failed", monotonic_now_us(), {{"state", net::connection_state_name(status.state)}, {"reason", status.reason}});
    std::cerr << "site " << common_.name << ": no connection to the other site within " << options.connect_timeout_s
              << " s of the start (" << net::connection_state_name(status.state)
              << (status.reason.empty() ? "" : ": " + status.reason) << ")\n";
    return 2;
  }
  common_.epoch_us = monotonic_now_us();
  common_.end_us = common_.epoch_us + uint64_t(common_.scene.duration_s() / options.time_scale * 1e6);
  events_.write("connected", common_.epoch_us, {{"peer", net_->status().peer}});
  std::cout << "connected" << std::endl;

  touch_->loop().start();
  sound_->start(marker_claps_us());
  // A stage that throws ends the run cleanly: the others see `stopping` and the error is reported.
  std::atomic<bool> failed{false};
  auto guarded = [&](const char* stage, auto loop) {
    return std::thread([this, stage, loop, &failed] {
      try {
        loop();
      } catch (const std::exception& error) {
        std::cerr << "site " << common_.name << ": " << stage << " failed: " << error.what() << "\n";
        events_.write("error", monotonic_now_us(), {{"stage", stage}, {"message", error.what()}});
        failed = true;
        common_.stopping = true;
        common_.sender_done = true;
        sender_->stop();
        receiver_->stop();
      }
    });
  };
  std::thread tracker = guarded("tracker", [this] { sender_->tracker_loop(); });
  std::thread capture = guarded("capture", [this] { sender_->capture_loop(); });
  std::thread ibr = guarded("image-based rendering", [this] { sender_->ibr_loop(); });
  std::thread display = guarded("display", [this] { receiver_->display_loop(); });

  std::atomic<bool> display_finished{false};
  std::thread display_watch([&] {
    display.join();
    display_finished = true;
  });
  monitor(display_finished);
  display_watch.join();
  common_.stopping = true;
  capture.join();
  ibr.join();
  tracker.join();
  touch_->loop().stop();
  sound_->stop();
  put_sound_into_video();
  const double elapsed_s = double(monotonic_now_us() - common_.epoch_us) * 1e-6;
  // Give the peer a moment to take our last messages before the connection closes.
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  nlohmann::json m = site_metrics(common_, elapsed_s);
  sender_->add_metrics(m, std::max(elapsed_s, 1e-6));
  receiver_->add_metrics(m, std::max(elapsed_s, 1e-6));
  m["motor"] = motor_.description;
  m["sound"] = sound_->metrics();
  // Sound against picture (ITU-R BT.1359 allows the sound 45 ms early to 125 ms late): the far
  // voice's capture-to-play latency less the far portrait's capture-to-screen latency. Both are
  // differences of the other site's clock to this one's, whose offset cancels here.
  if (const double voice = sound_->voice_latency_ms(), picture = receiver_->portrait_latency_ms();
      std::isfinite(voice) && std::isfinite(picture))
    m["sound"]["voice_minus_portrait_ms"] = voice - picture;
  m["latency_ms"]["touch_to_motor_command"] = touch_to_motor_.to_json();
  m["latency_ms"]["touch_detected_to_motor_command"] = detect_to_motor_.to_json();
  m["fps"]["touch_loop"] = double(touch_->loop().ticks()) / std::max(elapsed_s, 1e-6);
  const MotorTimingCounts pulses = touch_->loop().motor_counts();
  m["touch"]["settings"] = touch_settings_json(options.touch);
  m["touch"]["pulses"] = {{"predicted", pulses.predicted},
                          {"confirmed", pulses.confirmed},
                          {"cancelled", pulses.cancelled},
                          {"unpredicted", pulses.unpredicted}};
  m["touch"]["contact_to_vibration_ms"] = contact_to_vibration();
  // Each touch's sound against the scene's true contact nearest it, where the truth is known.
  if (const nlohmann::json& truth = m["touch"]["contact_to_vibration_ms"]; truth.is_object() && m["sound"].contains("touch_sounds"))
    for (nlohmann::json& sound : m["sound"]["touch_sounds"]["sounds"]) {
      double nearest_ms = NAN;
      for (const nlohmann::json& touch : truth["touches"]) {
        const double ms = (sound["onset_us"].get<double>() - touch["contact_us"].get<double>()) / 1000.0;
        if (!(std::abs(ms) >= std::abs(nearest_ms))) nearest_ms = ms;
      }
      sound["onset_minus_true_contact_ms"] = std::isfinite(nearest_ms) ? nlohmann::json(nearest_ms) : nlohmann::json();
    }
  if (options.run.capture_frame >= 0) m["capture"] = capture_->to_json();
  m["stopped_by"] = stopped_by_.empty() ? nlohmann::json() : nlohmann::json(stopped_by_);
  m["display"] = display_mode_ == DisplayMode::Window ? "window" : display_mode_ == DisplayMode::Both ? "both" : "headless";
  m["connected"] = true;
  net_->stop();
  std::ofstream(common_.out / "metrics.json") << m.dump(2) << "\n";
  capture_->report();
  if (options.run.profile) print_profile(common_.name, m["gpu_ms"]);
  if (!options.progress_lines) {
    std::cout << "\n";
    print_table_row("", {"site " + common_.name});
    for (const auto& [name, cell] : closing_rows(m)) print_table_row(name, {cell});
    std::cout << std::flush;
    std::cerr << "site " << common_.name << ": written to " << common_.out.string() << ": events.jsonl, metrics.json"
              << (common_.write_frames ? ", frames/, site.mp4" : "") << "\n";
  }
  if (failed) return 1;
  if (g_stop_signal) return 128 + g_stop_signal;  // stopped, not finished: as a shell reports it
  vk::Context& context = gpu_.context();
  if (context.validation_enabled() && context.validation_errors() > 0) {
    std::cerr << "site " << common_.name << ": " << context.validation_errors() << " validation errors\n";
    return 1;
  }
  std::cout << "done" << std::endl;
  return 0;
}

}  // namespace

int run_site(const SiteRunOptions& given) {
  if (given.key_file.empty()) throw std::invalid_argument("a site needs --key-file (64 hex digits, the same at both sites)");
  SiteRunOptions options = given;
  sim::resolve_scene(options.scene);  // an unknown scene is refused before the device starts
  const DisplayMode display = parse_display_mode(options.display, display_present());
  if (display != DisplayMode::Headless) {
    // The window's surface needs these from the instance, and the device must present.
    options.run.surface_instance_extensions = display::GlfwWindow::surface_instance_extensions();
    options.run.presentation = true;
  }
  if (display == DisplayMode::Window) options.write_truth = false;  // no files to compare it with
  const uint64_t started_us = monotonic_now_us();
  install_stop_handlers();
  session::OutputFolderLock out_lock(options.run.out, "--out");
  SiteRun site(options, started_us);
  return site.run();
}

}  // namespace rt::site
