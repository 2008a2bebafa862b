#include "site/site_run.h"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include <atomic>
#include <cmath>
#include <cstdio>
#include <deque>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <thread>

#include "config/assets.h"
#include "pipeline/demo_layers.h"
#include "pipeline/gpu_session.h"
#include "pipeline/hand_renderer.h"
#include "pipeline/ibr_renderer.h"
#include "site/site_display.h"
#include "site/site_eye.h"
#include "site/site_inputs.h"
#include "site/site_motor.h"
#include "pipeline/site_simulator.h"
#include "geometry/target_view.h"
#include "ibr/camera_selection.h"
#include "image/image_crop.h"
#include "image/image_io.h"
#include "net/session.h"
#include "passes/composite.h"
#include "passes/hand_alpha.h"
#include "passes/overlay.h"
#include "session/event_log.h"
#include "session/fair_mutex.h"
#include "session/latency_stats.h"
#include "session/mailbox.h"
#include "session/timed_history.h"
#include "sim/tracker_sim.h"
#include "time/monotonic_clock.h"
#include "touch/touch_loop.h"

namespace rt::site {
namespace {

using Clock = std::chrono::steady_clock;
const std::filesystem::path kTemplateDir = config::assets_dir() / "hand";
constexpr auto kMotorPulse = std::chrono::milliseconds(150);
constexpr int kMotorStrength = 200;

struct CapturedFrame {
  uint64_t index = 0;
  uint64_t capture_us = 0;  // monotonic, when the cameras' images were taken
  double scene_time_s = 0;  // of the frame, for the tracked hands of that moment
  sim::RgbdFrame frame;
};

struct ReceivedPortrait {
  net::PortraitMessage message;
  uint64_t arrival_us = 0;
};

// Renders kept for the display to choose from. The portrait arrives a few hundred milliseconds
// after its skeleton on lavapipe; the hand thread renders once per camera frame, so this covers
// about 0.8 s at 30 fps scene time, and more when the scene plays slower.
constexpr size_t kHandRenderHistory = 24;
// The hand render nearest the portrait's time can still be off by the hand thread's spacing (one
// camera frame, more when the GPU is busy; metrics.json reports the gap). Near the glass a hand
// a little off beats no hand, as the cameras cannot see it there; beyond this it is the wrong
// hand altogether (a stalled thread), and the portrait is shown alone.
constexpr uint64_t kMaxHandToPortraitGapUs = 500'000;

uint64_t gap_us(uint64_t a, uint64_t b) { return a > b ? a - b : b - a; }

// While the link is down, a frame this often shows the user that the remote side is lost.
constexpr uint64_t kLinkLostFrameIntervalUs = 250'000;

std::vector<passes::IbrCameraModel> camera_models(pipeline::RgbdRenderer& renderer) {
  std::vector<passes::IbrCameraModel> models;
  for (size_t k = 0; k < renderer.camera_count(); ++k) models.push_back({renderer.camera(k).color, renderer.camera(k).depth});
  return models;
}

nlohmann::json timings_json(const vk::FrameGraph& graph) {
  nlohmann::json out = nlohmann::json::object();
  double total = 0;
  for (const auto& timing : graph.timings()) {
    out[timing.name] = timing.median_ms;
    total += timing.median_ms;
  }
  out["total"] = total;
  return out;
}

class SiteRun {
 public:
  explicit SiteRun(const SiteRunOptions& options);
  int run();

 private:
  void capture_loop();
  void ibr_loop();
  void tracker_loop();
  void hand_loop();
  void display_loop();
  void on_message(const net::Message& message);
  void on_touch(const TouchEvent& event);
  double scene_time_s(uint64_t now_us) const { return double(now_us - epoch_us_) * 1e-6 * options_.time_scale; }
  nlohmann::json metrics(double elapsed_s);

  SiteRunOptions options_;
  const std::string site_name_;
  const Site remote_;
  sim::Scene scene_;
  uint32_t width_, height_;
  std::filesystem::path out_;
  pipeline::GpuSession gpu_;
  vk::Context& context_;
  session::FairMutex gpu_turn_;
  session::EventLog events_;
  HostImage background_;

  // The site's inputs (site_inputs.h): simulated from the scene, or replayed from a recording.
  std::unique_ptr<pipeline::SiteSimulator> simulator_;
  std::unique_ptr<SiteReplay> replay_;
  TrackedHandsHistory tracked_hands_;
  std::unique_ptr<pipeline::IbrRenderer> ibr_;
  std::vector<Eigen::Vector3d> camera_positions_;
  std::unique_ptr<net::Session> net_;
  SiteMotor motor_;  // used by the touch loop's thread only (usb_motor.h)
  std::unique_ptr<ViewerEyeFinder> eye_finder_;
  std::unique_ptr<TouchLoop> touch_;

  session::Mailbox<CapturedFrame> captured_;
  session::Mailbox<ReceivedPortrait> portraits_;
  std::mutex eye_mutex_;
  std::optional<Eigen::Vector3d> remote_eye_;  // the remote viewer's eye, in this site's frame
  std::mutex skeleton_mutex_;
  std::deque<std::pair<uint64_t, uint64_t>> remote_capture_of_arrival_;  // (arrival, sender's capture) µs
  session::TimedHistory<net::SkeletonMessage> remote_skeletons_{100};  // sender's frame and clock: 2 s at 50 Hz
  // The hand thread: the newest remote skeleton to draw, the view to draw it from (the portraits'
  // camera, sent with each one), the portraits shown (for appearance adaption), its renders.
  session::Mailbox<net::SkeletonMessage> skeletons_to_draw_;
  session::Mailbox<ReceivedPortrait> portraits_shown_;
  std::mutex hand_camera_mutex_;
  std::optional<Camera> hand_camera_;
  session::TimedHistory<HandRender> hand_renders_{kHandRenderHistory};
  std::atomic<bool> display_done_{false};

  uint64_t epoch_us_ = 0, end_us_ = 0;
  std::atomic<bool> stopping_{false}, capture_done_{false}, ibr_done_{false};
  std::atomic<uint64_t> frames_captured_{0}, portraits_sent_{0}, frames_without_eye_{0}, tracker_ticks_{0};
  std::atomic<uint64_t> hand_renders_done_{0}, link_lost_frames_{0}, frames_displayed_{0}, portraits_wrong_size_{0},
      last_scene_frame_{0}, truth_frames_{0};
  std::atomic<uint64_t> last_portrait_arrival_us_{0};
  session::LatencyStats hand_to_portrait_gap_;  // capture times of the hand render and the portrait fused
  session::LatencyStats capture_to_sent_, portrait_on_screen_, portrait_network_, hand_on_screen_, touch_to_motor_,
      detect_to_motor_;
  // Wall time of each stage's GPU turn (upload, graph run, download), next to the frame graph's
  // per-pass timestamps.
  session::LatencyStats simulator_wall_, ibr_wall_, hand_wall_, receiver_wall_;
  nlohmann::json gpu_ms_;
  std::mutex gpu_ms_mutex_;
};

SiteRun::SiteRun(const SiteRunOptions& options)
    : options_(options),
      site_name_(site_name(options.site)),
      remote_(other_site(options.site)),
      scene_(sim::load_scene(sim::resolve_scene(options.scene))),
      width_(options.run.width),
      height_(options.run.height),
      out_(options.run.out),
      gpu_((std::filesystem::create_directories(options.run.out), options.run)),
      context_(gpu_.context()),
      events_(options.run.out / "events.jsonl", site_name(options.site)),
      background_(pipeline::make_demo_layers(width_, height_).background) {
  if (options_.frames_given) scene_.frame_count = options_.run.frames;
  if (options_.resolution_scale > 0) scene_.resolution_scale = options_.resolution_scale;
  if (!(options_.time_scale > 0) || !std::isfinite(options_.time_scale))
    throw std::invalid_argument("--time-scale must be > 0");
  std::filesystem::create_directories(out_ / "frames");
  if (options_.write_truth) std::filesystem::create_directories(out_ / "truth");

  pipeline::IbrSettings settings;
  settings.width = width_;
  settings.height = height_;
  std::vector<passes::IbrCameraModel> cameras;
  if (!options_.replay.empty()) {
    // The recording stands for this site's devices: its calibration is the site, its frames and
    // its times are the scene's.
    replay_ = std::make_unique<SiteReplay>(options_.replay, options_.frames_given ? options_.run.frames : 0, settings.views);
    scene_.sites[options_.site == Site::A ? 0 : 1].site = replay_->site();
    scene_.frame_count = uint32_t(replay_->frame_count());
    scene_.fps = replay_->pacing().fps(scene_.fps);
    cameras = replay_->cameras();
    std::cerr << "site " << site_name_ << ": replaying " << replay_->frame_count() << " frames of " << options_.replay.string()
              << " (" << scene_.duration_s() << " s of scene time)" << (options_.resolution_scale > 0 ? "; --resolution-scale does not apply to a replay" : "")
              << "\n";
  } else {
    simulator_ = std::make_unique<pipeline::SiteSimulator>(context_, scene_, options_.site, options_.write_truth ? width_ : 0,
                                                 options_.write_truth ? height_ : 0);
    cameras = camera_models(simulator_->renderer());
  }
  ibr_ = std::make_unique<pipeline::IbrRenderer>(context_, cameras, settings);
  for (const auto& camera : scene_.at(options_.site).site.cameras) camera_positions_.push_back(camera.color_camera().position_in_site());

  motor_ = open_site_motor(parse_motor_mode(options_.motor), [this](const std::string& line) {
    std::cerr << "site " << site_name_ << ": motor: " << line << "\n";
    events_.write("motor_log", monotonic_now_us(), {{"line", line}});
  });
  std::cerr << "site " << site_name_ << ": motor: " << motor_.description << "\n";
  events_.write("motor", monotonic_now_us(), {{"motor", motor_.description}});

  // The eye sent to the peer: the seat's head position until the cameras find the viewer's eyes.
  std::vector<Camera> color_cameras;
  for (const auto& camera : cameras) color_cameras.push_back(camera.color);
  eye_finder_ = std::make_unique<ViewerEyeFinder>(
      color_cameras, scene_.at(options_.site).site.seat.head_centre_m, EyeSearchOptions{}, [this](const std::string& source) {
        std::cerr << "site " << site_name_ << ": eye: " << source << "\n";
        events_.write("eye_source", monotonic_now_us(), {{"source", source}});
      });

  // A skeleton counts as lost after 200 ms rather than 100, and a touch holds for a second without
  // news: the tracker thread shares two CPU cores with a CPU Vulkan driver here, and a late tick
  // is not a hand the tracker lost.
  TouchParameters touch_parameters;
  touch_parameters.max_skeleton_age_us = 200'000;
  touch_parameters.touch_hold_age_us = 1'000'000;
  touch_ = std::make_unique<TouchLoop>(touch_parameters, [this](const TouchEvent& event) { on_touch(event); });

  net::SessionOptions net_options;
  net_options.key = net::load_session_key_file(options_.key_file);
  net_options.name = "site " + site_name_;
  if (options_.peer.empty()) {
    net_options.role = net::Role::Listener;
    // Port 0 (any free port) is fine for a listener, which parse_host_port refuses for a peer.
    const size_t colon = options_.listen.rfind(':');
    if (colon != std::string::npos && options_.listen.substr(colon) == ":0") {
      net_options.host = options_.listen.substr(0, colon);
      net_options.port = 0;
    } else {
      std::tie(net_options.host, net_options.port) = net::parse_host_port(options_.listen);
    }
  } else {
    net_options.role = net::Role::Connector;
    std::tie(net_options.host, net_options.port) = net::parse_host_port(options_.peer);
  }
  net_options.log = [this](const std::string& line) {
    std::cerr << line << "\n";
    events_.write("net_log", monotonic_now_us(), {{"line", line}});
  };
  net_ = std::make_unique<net::Session>(net_options);
  net_->set_handler([this](const net::Message& message) { on_message(message); });
}

void SiteRun::on_message(const net::Message& message) {
  const uint64_t now = monotonic_now_us();
  if (const auto* eye = std::get_if<net::EyeMessage>(&message)) {
    if (!eye->valid) return;
    std::lock_guard lock(eye_mutex_);
    remote_eye_ = map_point(remote_, options_.site, eye->eye);
  } else if (const auto* skeleton = std::get_if<net::SkeletonMessage>(&message)) {
    // The detector's "lost tracking" age is measured from arrival: the link's delay is not the
    // tracker losing the hand (and two machines' clocks are unrelated anyway). The capture time
    // is kept aside for the touch-to-motor latency.
    std::vector<HandSkeleton> hands;
    for (const auto& hand : skeleton->hands) {
      HandSkeleton local = map_skeleton(remote_, options_.site, hand);
      local.timestamp_us = now;
      hands.push_back(local);
    }
    {
      std::lock_guard lock(skeleton_mutex_);
      remote_capture_of_arrival_.emplace_back(now, skeleton->timestamp_us);
      while (remote_capture_of_arrival_.size() > 200) remote_capture_of_arrival_.pop_front();
    }
    touch_->set_remote_hands(std::move(hands));
    skeletons_to_draw_.put(*skeleton);
    remote_skeletons_.add(skeleton->timestamp_us, *skeleton);
  } else if (const auto* portrait = std::get_if<net::PortraitMessage>(&message)) {
    portrait_network_.add(double(int64_t(now) - int64_t(portrait->capture_timestamp_us)) / 1000.0);
    last_portrait_arrival_us_ = now;
    portraits_.put({*portrait, now});
  } else if (const auto* touch = std::get_if<net::TouchEventMessage>(&message)) {
    events_.write(touch->kind == net::TouchEventMessage::Kind::Start ? "remote_touch_start" : "remote_touch_end", now,
                  {{"detected_by", touch->site == 0 ? "A" : "B"}});
  }
}

void SiteRun::on_touch(const TouchEvent& event) {
  const bool start = event.kind == TouchEvent::Kind::Start;
  events_.write(start ? "touch_start" : "touch_end", event.timestamp_us,
                {{"overlap_cm2", event.overlap_area_m2 * 1e4},
                 {"local_capture_us", event.local_capture_us},
                 {"remote_capture_us", event.remote_capture_us}});
  net::TouchEventMessage message;
  message.timestamp_us = event.timestamp_us;
  message.kind = start ? net::TouchEventMessage::Kind::Start : net::TouchEventMessage::Kind::End;
  message.site = options_.site == Site::A ? 0 : 1;
  net_->send(message);
  if (!start) return;
  const uint64_t command_us = monotonic_now_us();
  const motor::MotorStatus status = motor_.motor->pulse(kMotorPulse, kMotorStrength);
  if (!status) {
    events_.write("motor_error", command_us, {{"error", status.error()}});
    return;
  }
  // The hands met when the later of the two skeletons that showed it was captured.
  uint64_t remote_capture_us = 0;
  {
    std::lock_guard lock(skeleton_mutex_);
    for (const auto& [arrival, capture] : remote_capture_of_arrival_)
      if (arrival == event.remote_capture_us) remote_capture_us = capture;
  }
  const uint64_t met_us = remote_capture_us ? std::max(event.local_capture_us, remote_capture_us) : 0;
  const double met_to_motor_ms = met_us ? double(int64_t(command_us) - int64_t(met_us)) / 1000.0 : NAN;
  touch_to_motor_.add(met_to_motor_ms);
  detect_to_motor_.add(double(int64_t(command_us) - int64_t(event.timestamp_us)) / 1000.0);
  events_.write("motor_pulse", command_us,
                {{"duration_ms", kMotorPulse.count()}, {"strength", kMotorStrength},
                 {"touch_to_motor_ms", std::isfinite(met_to_motor_ms) ? nlohmann::json(met_to_motor_ms) : nlohmann::json()}});
}

void SiteRun::capture_loop() {
  const double fps = scene_.fps;
  uint64_t last_index = UINT64_MAX;
  bool told_no_truth = false;
  while (!stopping_) {
    const uint64_t now = monotonic_now_us();
    // The cameras' frame due now: the simulator renders the scene's frame of this moment, a replay
    // takes the newest recorded frame whose time has come; either skips the frames it missed.
    std::optional<uint64_t> due;
    double next_s = 0;  // when the frame after `last_index` is due
    if (replay_) {
      if (const auto i = replay_->pacing().due_at(scene_time_s(now))) due = *i;
      if (due && *due == last_index && last_index + 1 >= replay_->frame_count()) break;
      next_s = replay_->pacing().time_s(due && *due == last_index ? last_index + 1 : 0);
    } else {
      due = uint64_t(std::floor(scene_time_s(now) * fps));
      if (*due >= scene_.frame_count) break;
      next_s = double(*due + 1) / fps;
    }
    if (!due || *due == last_index) {  // wait for the cameras' next frame
      const uint64_t due_us = epoch_us_ + uint64_t(next_s / options_.time_scale * 1e6);
      std::this_thread::sleep_for(std::chrono::microseconds(due_us > now ? due_us - now : 0));
      continue;
    }
    const uint64_t index = *due;
    last_index = index;
    last_scene_frame_ = index;
    CapturedFrame captured;
    captured.index = index;
    HostImage truth;
    if (replay_) {
      captured.frame = replay_->read(index);  // files only: no GPU turn
      captured.capture_us = monotonic_now_us();
      captured.scene_time_s = replay_->pacing().time_s(index);
      if (options_.write_truth) {
        // The recording's ground truth is the view from the seat of the scene it was made in.
        std::optional<HostImage> recorded = replay_->ground_truth(index);
        if (recorded && recorded->width == width_ && recorded->height == height_ && recorded->channels() == 4) {
          truth = std::move(*recorded);
        } else if (!told_no_truth) {
          told_no_truth = true;
          const std::string why = recorded ? "its gt/ target view is " + std::to_string(recorded->width) + "x" +
                                                 std::to_string(recorded->height) + ", not the display's " +
                                                 std::to_string(width_) + "x" + std::to_string(height_)
                                           : "it has no gt/ target view for frame " + std::to_string(index);
          events_.write("warning", monotonic_now_us(), {{"message", "no ground truth from the recording: " + why}});
        }
      }
    } else {
      std::lock_guard turn(gpu_turn_);
      const uint64_t start = monotonic_now_us();
      simulator_->seek(index);
      std::optional<sim::RgbdFrame> frame = simulator_->next_frame();
      if (!frame) break;
      captured.capture_us = monotonic_now_us();
      captured.frame = std::move(*frame);
      captured.scene_time_s = double(index) / fps;
      if (options_.write_truth) truth = simulator_->renderer().target_color();
      simulator_wall_.add(double(monotonic_now_us() - start) / 1000.0);
    }
    // The viewer's eyes are looked for in the first frames, on the finder's own thread.
    if (eye_finder_->wants_frame()) eye_finder_->offer(captured.capture_us, captured.frame.cameras);
    ++frames_captured_;
    captured_.put(std::move(captured));
    if (!truth.texels.empty()) {
      write_image(out_ / "truth" / frame_name(index), truth_over_background(truth, background_));
      ++truth_frames_;
    }
  }
  capture_done_ = true;
  captured_.close();
}

void SiteRun::ibr_loop() {
  while (true) {
    std::optional<CapturedFrame> captured = captured_.wait_take(std::chrono::milliseconds(50));
    if (!captured) {
      if (captured_.closed()) break;
      continue;
    }
    std::optional<Eigen::Vector3d> eye;
    {
      std::lock_guard lock(eye_mutex_);
      eye = remote_eye_;
    }
    if (!eye) {  // nobody to render for yet
      ++frames_without_eye_;
      continue;
    }
    const Camera target = target_view_camera(*eye, scene_.at(options_.site).site.screen, width_, height_);
    // The cameras opposite the hand the tracker saw reaching at that moment (no ground truth here).
    const std::vector<HandSkeleton> hands = tracked_hands_.closest(captured->scene_time_s).value_or(std::vector<HandSkeleton>{});
    const auto selection = ibr::select_cameras(camera_positions_, touching_side(hands), ibr_->settings().views);
    net::PortraitMessage message;
    {
      std::lock_guard turn(gpu_turn_);
      const uint64_t start = monotonic_now_us();
      ibr_->render(captured->frame.cameras, selection, target);
      message.color = vk::download(context_, ibr_->portrait());
      message.depth = vk::download(context_, ibr_->portrait_depth());
      ibr_wall_.add(double(monotonic_now_us() - start) / 1000.0);
    }
    message.frame_index = captured->index;
    message.capture_timestamp_us = captured->capture_us;
    message.width = width_;
    message.height = height_;
    message.fx = target.intrinsics.fx;
    message.fy = target.intrinsics.fy;
    message.cx = target.intrinsics.cx;
    message.cy = target.intrinsics.cy;
    message.camera_from_site = target.camera_from_site.matrix();
    net_->send(message);  // encodes here, on this thread
    ++portraits_sent_;
    capture_to_sent_.add(double(monotonic_now_us() - captured->capture_us) / 1000.0);
  }
  ibr_done_ = true;
}

void SiteRun::tracker_loop() {
  const sim::SiteDescription& site = scene_.at(options_.site).site;
  PacedHandTracker tracker =
      replay_ ? PacedHandTracker(replay_->tracker(), site.tracker, replay_->origin_us())
              : PacedHandTracker(std::make_unique<sim::SimulatedHandTracker>(sim::make_simulated_tracker(scene_, options_.site)),
                                 site.tracker, 0);
  std::optional<Eigen::Vector3d> sent_eye;
  auto next = Clock::now();
  for (uint64_t tick = 0; !stopping_; ++tick) {
    const uint64_t now = monotonic_now_us();
    // The paper computes the viewpoint once; sent again every half second so that a peer that
    // reconnects gets it too, and at once when the cameras' eye replaces the seat's.
    const Eigen::Vector3d eye = eye_finder_->eye();
    if (tick % 25 == 0 || !sent_eye || *sent_eye != eye) {
      net_->send(net::EyeMessage{now, eye, true});
      sent_eye = eye;
    }
    std::vector<HandSkeleton> hands;
    if (const auto tracked = tracker.at(scene_time_s(now))) {
      tracked_hands_.add(tracked->time_s, tracked->hands);
      hands = tracked->hands;
      // Ages count on this machine's clock from when the site has the frame.
      for (auto& hand : hands) hand.timestamp_us = now;
    }
    touch_->set_local_hands(hands);
    net_->send(net::SkeletonMessage{now, hands});
    ++tracker_ticks_;
    next += std::chrono::microseconds(sim::kTrackerPeriodUs);
    std::this_thread::sleep_until(next);
  }
}

void SiteRun::hand_loop() {
  // Declared first, so destroyed last: the hand's Vulkan objects go while this holds the turn.
  std::unique_lock<session::FairMutex> final_turn(gpu_turn_, std::defer_lock);
  vk::Image portrait(context_, {"adaption portrait", width_, height_, PixelFormat::RGBA32F});
  vk::Image portrait_depth(context_, {"adaption portrait depth", width_, height_, PixelFormat::R32F});
  pipeline::HandRenderer hand(context_, kTemplateDir, width_, height_);
  vk::FrameGraph graph(context_, "geometry hand");
  {
    std::lock_guard turn(gpu_turn_);
    hand.add_to(graph);
  }
  // The skeleton's hand nearest the glass, posed for `camera` (the portraits' view, in the sender's
  // frame like the skeleton); a skeleton that cannot be posed keeps the last pose.
  auto pose = [&](const net::SkeletonMessage& skeleton, const Camera& camera) {
    const HandSkeleton* drawn = touching(skeleton.hands);
    if (drawn) hand.set_pose(*drawn, camera);
    return drawn && hand.has_pose();
  };
  // Skinning and rasterization, read back cut to the hand; the caller holds the GPU turn.
  auto render_in_turn = [&] {
    const uint64_t start = monotonic_now_us();
    graph.run();
    HandRender render = cropped_hand_render(vk::download(context_, hand.color()), vk::download(context_, hand.mask()),
                                            float(hand.hand_distance_m()));
    hand_wall_.add(double(monotonic_now_us() - start) / 1000.0);
    ++hand_renders_done_;
    return render;
  };
  // One render per camera frame is all the display can use; more would only take GPU turns
  // from the image-based model (lavapipe has one GPU's worth of CPU for everything).
  const auto period = std::chrono::microseconds(
      std::max<int64_t>(sim::kTrackerPeriodUs, int64_t(1e6 / (scene_.fps * options_.time_scale))));
  auto next = Clock::now();
  while (!display_done_ && !stopping_) {
    // Appearance adaption (Eq. 3) compares a shown portrait with the hand posed at its capture
    // time, in its view; the adapted texture is what the next renders sample. Only where the
    // cameras see the hand well (beyond d_max), as adapt_appearance_from requires anyway.
    if (std::optional<ReceivedPortrait> shown = portraits_shown_.take()) {
      const net::PortraitMessage& message = shown->message;
      const auto skeleton = remote_skeletons_.closest(message.capture_timestamp_us);
      if (skeleton && pose(skeleton->second, portrait_camera(message)) && hand.appearance_adaption_possible()) {
        // Urgent like the display: the receiver's work is what the user waits for.
        session::UrgentTurn turn(gpu_turn_);
        hand_renders_.add(skeleton->first, render_in_turn());
        vk::upload(context_, portrait, message.color);
        vk::upload(context_, portrait_depth, message.depth);
        (void)hand.adapt_appearance_from(portrait, portrait_depth);
      }
    }
    std::optional<net::SkeletonMessage> skeleton = skeletons_to_draw_.wait_take(std::chrono::milliseconds(50));
    std::optional<Camera> camera;
    {
      std::lock_guard lock(hand_camera_mutex_);
      camera = hand_camera_;
    }
    if (!skeleton || !camera) continue;  // nothing new, or no portrait yet to say from where
    if (pose(*skeleton, *camera)) {
      session::UrgentTurn turn(gpu_turn_);
      hand_renders_.add(skeleton->timestamp_us, render_in_turn());
    } else {
      hand_renders_.add(skeleton->timestamp_us, HandRender{});  // no hand near: the portrait alone
    }
    next += period;
    const auto now = Clock::now();
    if (next < now) next = now;  // fell behind: skip, do not burst
    std::this_thread::sleep_until(next);
  }
  {
    std::lock_guard lock(gpu_ms_mutex_);
    gpu_ms_["hand"] = timings_json(graph);
    if (hand.appearance_graph()) gpu_ms_["appearance"] = timings_json(*hand.appearance_graph());
  }
  final_turn.lock();
}

void SiteRun::display_loop() {
  // Declared first, so destroyed last: the receiver's Vulkan objects go while this holds the turn.
  std::unique_lock<session::FairMutex> final_turn(gpu_turn_, std::defer_lock);
  vk::Image portrait(context_, {"portrait", width_, height_, PixelFormat::RGBA32F});
  vk::Image background(context_, {"background", width_, height_, PixelFormat::RGBA32F});
  vk::Image hand_color(context_, {"hand color", width_, height_, PixelFormat::RGBA32F});
  vk::Image hand_mask(context_, {"hand mask", width_, height_, PixelFormat::R32F});
  vk::Image hand_alpha(context_, {"hand alpha", width_, height_, PixelFormat::R32F});
  vk::Image fused(context_, {"fused", width_, height_, PixelFormat::RGBA32F});
  vk::Image display(context_, {"display", width_, height_, PixelFormat::RGBA8});
  passes::HandAlphaPass alpha_pass(context_);
  passes::OverlayPass overlay_pass(context_);
  passes::CompositePass composite_pass(context_);
  vk::FrameGraph graph(context_, "receiver frame");
  float hand_distance_m = NAN;
  {
    std::lock_guard turn(gpu_turn_);
    vk::upload(context_, background, background_);
    alpha_pass.add_to(graph, hand_mask, hand_alpha, [&] { return hand_distance_m; });
    overlay_pass.add_to(graph, hand_color, hand_alpha, portrait, fused);
    composite_pass.add_to(graph, fused, background, display);
  }
  cv::VideoWriter video(out_ / "site.mp4", cv::VideoWriter::fourcc('m', 'p', '4', 'v'), scene_.fps,
                        cv::Size(int(width_), int(height_)));
  if (!video.isOpened()) events_.write("warning", monotonic_now_us(), {{"message", "OpenCV cannot write site.mp4 here"}});
  std::ofstream frames_log(out_ / "frames.jsonl");
  std::optional<uint64_t> last_video_frame;
  const HostImage no_portrait(width_, height_, PixelFormat::RGBA32F);
  uint64_t last_shown_us = 0;
  // A displayed frame: PNG, `video_repeat` frames of the MP4, a line of frames.jsonl.
  auto write_frame = [&](const cv::Mat& bgr, nlohmann::json entry, uint64_t video_repeat) {
    const uint64_t display_index = frames_displayed_++;
    cv::imwrite((out_ / "frames" / frame_name(display_index)).string(), bgr);
    if (video.isOpened())
      for (uint64_t i = 0; i < video_repeat; ++i) video.write(bgr);
    entry["display"] = display_index;
    frames_log << entry.dump() << "\n";
  };

  while (true) {
    std::optional<ReceivedPortrait> received = portraits_.wait_take(std::chrono::milliseconds(50));
    if (!received) {
      const uint64_t now = monotonic_now_us();
      const uint64_t quiet_since = std::max<uint64_t>(last_portrait_arrival_us_, end_us_);
      // Before the first portrait, the peer may still be starting up on a loaded machine: wait
      // longer for it than for the tail of a stream that has been flowing.
      const double linger_s = last_portrait_arrival_us_ ? options_.linger_s : std::max(options_.linger_s, 10.0);
      if (ibr_done_ && now > end_us_ && now - quiet_since > uint64_t(linger_s * 1e6)) break;
      if (now > end_us_ + 30'000'000) break;  // the peer is gone for good
      if (stopping_) break;
      // While the link is down the display keeps running and says so (after the scene's end, a
      // closing peer is the normal shutdown).
      if (now < end_us_ && now - last_shown_us >= kLinkLostFrameIntervalUs &&
          net_->status().state != net::ConnectionState::Connected) {
        HostImage frame;
        {
          session::UrgentTurn turn(gpu_turn_);
          vk::upload(context_, portrait, no_portrait);  // background only
          hand_distance_m = NAN;
          graph.run();
          frame = vk::download(context_, display);
        }
        cv::Mat bgr = to_bgr8(frame);
        label_link_lost(bgr, net_->status().reason);
        ++link_lost_frames_;
        write_frame(bgr, {{"portrait_frame", nullptr}, {"t_us", now}, {"link_lost", true}}, 1);
        last_shown_us = now;
      }
      continue;
    }
    const net::PortraitMessage& message = received->message;
    if (message.width != width_ || message.height != height_) {
      if (portraits_wrong_size_++ == 0)
        events_.write("error", monotonic_now_us(),
                      {{"message", "portrait is " + std::to_string(message.width) + "x" + std::to_string(message.height) +
                                       ", this site displays " + std::to_string(width_) + "x" + std::to_string(height_)}});
      continue;
    }
    {
      std::lock_guard lock(hand_camera_mutex_);
      hand_camera_ = portrait_camera(message);
    }
    // The hand render whose skeleton was captured closest to the portrait (both the sender's clock);
    // one far from it would put the hand where it no longer is: then the portrait shows alone.
    std::optional<std::pair<uint64_t, HandRender>> hand = hand_renders_.closest(message.capture_timestamp_us);
    if (hand && gap_us(hand->first, message.capture_timestamp_us) > kMaxHandToPortraitGapUs) hand.reset();
    const bool with_hand = hand && hand->second.drawn();
    HostImage shown;
    {
      session::UrgentTurn turn(gpu_turn_);
      vk::upload(context_, portrait, message.color);
      if (with_hand) {
        const PixelBox& box = hand->second.box;
        vk::upload(context_, hand_color, paste_on_zero(hand->second.color, box.x, box.y, width_, height_));
        vk::upload(context_, hand_mask, paste_on_zero(hand->second.mask, box.x, box.y, width_, height_));
      }
      hand_distance_m = with_hand ? hand->second.distance_m : NAN;
      const uint64_t start = monotonic_now_us();
      graph.run();
      shown = vk::download(context_, display);
      receiver_wall_.add(double(monotonic_now_us() - start) / 1000.0);
    }
    const uint64_t on_screen = monotonic_now_us();
    last_shown_us = on_screen;
    portrait_on_screen_.add(double(int64_t(on_screen) - int64_t(message.capture_timestamp_us)) / 1000.0);
    if (with_hand) {
      hand_on_screen_.add(double(int64_t(on_screen) - int64_t(hand->first)) / 1000.0);
      hand_to_portrait_gap_.add(double(gap_us(hand->first, message.capture_timestamp_us)) / 1000.0);
    }
    // The video plays in scene time: each displayed frame stays up until the next one's scene frame.
    const uint64_t repeat = last_video_frame ? std::clamp<uint64_t>(message.frame_index - *last_video_frame, 1, 90) : 1;
    last_video_frame = message.frame_index;
    const double hand_to_portrait_ms = hand ? double(int64_t(hand->first) - int64_t(message.capture_timestamp_us)) / 1000.0 : NAN;
    write_frame(to_bgr8(shown),
                {{"portrait_frame", message.frame_index},
                 {"t_us", on_screen},
                 {"hand_to_portrait_ms", std::isfinite(hand_to_portrait_ms) ? nlohmann::json(hand_to_portrait_ms) : nlohmann::json()},
                 {"hand_distance_m", std::isfinite(hand_distance_m) ? nlohmann::json(hand_distance_m) : nlohmann::json()}},
                repeat);
    portraits_shown_.put(std::move(*received));
  }
  display_done_ = true;
  {
    std::lock_guard lock(gpu_ms_mutex_);
    gpu_ms_["receiver"] = timings_json(graph);
  }
  final_turn.lock();
}

nlohmann::json SiteRun::metrics(double elapsed_s) {
  const net::NetCounters counters = net_->counters();
  nlohmann::json m;
  m["site"] = site_name_;
  m["scene"] = scene_.name;
  m["device"] = context_.device_name();
  m["width"] = width_;
  m["height"] = height_;
  m["scene_frames"] = scene_.frame_count;
  m["resolution_scale"] = scene_.resolution_scale;
  m["time_scale"] = options_.time_scale;
  m["elapsed_s"] = elapsed_s;
  m["inputs"] = replay_ ? "replay of " + replay_->dir().string() : std::string("simulated scene");
  m["eye_source"] = eye_finder_->source();
  m["eye"] = {eye_finder_->eye().x(), eye_finder_->eye().y(), eye_finder_->eye().z()};
  m["motor"] = motor_.description;
  {
    std::lock_guard lock(gpu_ms_mutex_);
    m["gpu_ms"] = gpu_ms_;
  }
  if (simulator_) m["gpu_ms"]["simulator"] = timings_json(simulator_->renderer().graph());
  m["gpu_ms"]["ibr"] = timings_json(ibr_->graph());
  m["stage_wall_ms"] = {{"simulator_render_and_readback", simulator_wall_.to_json()},
                        {"ibr_render_and_readback", ibr_wall_.to_json()},
                        {"hand_render_and_readback", hand_wall_.to_json()},
                        {"receiver_render_and_readback", receiver_wall_.to_json()}};
  m["latency_ms"] = {{"capture_to_portrait_sent", capture_to_sent_.to_json()},
                     {"capture_to_portrait_received", portrait_network_.to_json()},
                     {"capture_to_portrait_on_screen", portrait_on_screen_.to_json()},
                     {"skeleton_to_hand_on_screen", hand_on_screen_.to_json()},
                     {"hand_render_to_portrait_capture_gap", hand_to_portrait_gap_.to_json()},
                     {"touch_to_motor_command", touch_to_motor_.to_json()},
                     {"touch_detected_to_motor_command", detect_to_motor_.to_json()}};
  m["latency_notes"] =
      "portrait and hand: the remote sender's capture time to this site's display (both processes share the "
      "monotonic clock on one machine); touch: the later of the two skeletons that showed the touch to the motor command";
  const double wall = std::max(elapsed_s, 1e-6);
  m["fps"] = {{"capture", double(frames_captured_) / wall},
              {"portraits_sent", double(portraits_sent_) / wall},
              {"tracker", double(tracker_ticks_) / wall},
              {"hand_renders", double(hand_renders_done_) / wall},
              {"display", double(frames_displayed_) / wall},
              {"touch_loop", double(touch_->ticks()) / wall}};
  m["frames"] = {{"captured", frames_captured_.load()},
                 {"portraits_sent", portraits_sent_.load()},
                 {"displayed", frames_displayed_.load()},
                 {"displayed_link_lost", link_lost_frames_.load()},
                 {"dropped_before_ibr", captured_.dropped()},
                 {"dropped_without_remote_eye", frames_without_eye_.load()},
                 {"dropped_before_display", portraits_.dropped()},
                 {"portraits_stale_on_wire_out", counters.stale_dropped_out[net::message_type_index(net::MessageType::Portrait)]},
                 {"portraits_wrong_size", portraits_wrong_size_.load()},
                 {"ground_truth_written", truth_frames_.load()},
                 {"scene_frames_not_captured", scene_.frame_count - std::min<uint64_t>(scene_.frame_count, frames_captured_)}};
  m["bytes_per_s"] = {{"out", double(counters.bytes_out) / wall}, {"in", double(counters.bytes_in) / wall}};
  m["net"] = counters.to_json();
  m["touch"] = {{"starts", events_.count("touch_start")},
                {"ends", events_.count("touch_end")},
                {"motor_pulses", events_.count("motor_pulse")}};
  return m;
}

int SiteRun::run() {
  net_->start();
  if (options_.peer.empty()) std::cout << "listening on " << net_->local_port() << std::endl;
  events_.write("waiting_for_peer", monotonic_now_us(), {{"role", options_.peer.empty() ? "listener" : "connector"}});
  if (!net_->wait_connected(std::chrono::milliseconds(int64_t(options_.connect_timeout_s * 1000)))) {
    const net::ConnectionStatus status = net_->status();
    events_.write("connect_failed", monotonic_now_us(), {{"state", net::connection_state_name(status.state)}, {"reason", status.reason}});
    std::cerr << "site " << site_name_ << ": no connection to the other site within " << options_.connect_timeout_s
              << " s (" << net::connection_state_name(status.state) << (status.reason.empty() ? "" : ": " + status.reason)
              << ")\n";
    return 2;
  }
  epoch_us_ = monotonic_now_us();
  end_us_ = epoch_us_ + uint64_t(scene_.duration_s() / options_.time_scale * 1e6);
  events_.write("connected", epoch_us_, {{"peer", net_->status().peer}});
  std::cout << "connected" << std::endl;

  touch_->start();
  // A stage that throws ends the run cleanly: the others see `stopping_` and the error is reported.
  std::atomic<bool> failed{false};
  auto guarded = [&](const char* stage, void (SiteRun::*loop)()) {
    return std::thread([this, stage, loop, &failed] {
      try {
        (this->*loop)();
      } catch (const std::exception& error) {
        std::cerr << "site " << site_name_ << ": " << stage << " failed: " << error.what() << "\n";
        events_.write("error", monotonic_now_us(), {{"stage", stage}, {"message", error.what()}});
        failed = true;
        stopping_ = true;
        captured_.close();
        portraits_.close();
        ibr_done_ = true;
      }
    });
  };
  std::thread tracker = guarded("tracker", &SiteRun::tracker_loop);
  std::thread capture = guarded("capture", &SiteRun::capture_loop);
  std::thread ibr = guarded("image-based rendering", &SiteRun::ibr_loop);
  std::thread display = guarded("display", &SiteRun::display_loop);
  std::thread hand = guarded("hand rendering", &SiteRun::hand_loop);

  // The monitor: connection changes into the event log, progress for the parent.
  net::ConnectionState state = net::ConnectionState::Connected;
  uint64_t last_progress = UINT64_MAX;
  bool display_running = true;
  std::atomic<bool> display_finished{false};
  std::thread display_watch([&] {
    display.join();
    display_finished = true;
  });
  while (display_running) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    const uint64_t now = monotonic_now_us();
    const net::ConnectionStatus status = net_->status();
    if (status.state != state) {
      const bool after_scene = now > end_us_;
      if (status.state == net::ConnectionState::Connected)
        events_.write("connection_restored", now, {{"peer", status.peer}, {"phase", after_scene ? "shutdown" : "run"}});
      else if (state == net::ConnectionState::Connected)
        events_.write("connection_lost", now,
                      {{"state", net::connection_state_name(status.state)}, {"reason", status.reason},
                       {"phase", after_scene ? "shutdown" : "run"}});
      state = status.state;
    }
    const uint64_t frame = std::min<uint64_t>(last_scene_frame_ + 1, scene_.frame_count);
    if (frame != last_progress) {
      std::cout << "progress " << frame << " " << scene_.frame_count << std::endl;
      last_progress = frame;
    }
    display_running = !display_finished;
  }
  display_watch.join();
  stopping_ = true;
  capture.join();
  ibr.join();
  hand.join();
  tracker.join();
  touch_->stop();
  const double elapsed_s = double(monotonic_now_us() - epoch_us_) * 1e-6;
  // Give the peer a moment to take our last messages before the connection closes.
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  nlohmann::json m = metrics(elapsed_s);
  net_->stop();
  std::ofstream(out_ / "metrics.json") << m.dump(2) << "\n";
  if (failed) return 1;
  if (context_.validation_enabled() && context_.validation_errors() > 0) {
    std::cerr << "site " << site_name_ << ": " << context_.validation_errors() << " validation errors\n";
    return 1;
  }
  std::cout << "done" << std::endl;
  return 0;
}

}  // namespace

int run_site(const SiteRunOptions& options) {
  if (options.key_file.empty()) throw std::invalid_argument("a site needs --key-file (64 hex digits, the same at both sites)");
  SiteRun site(options);
  return site.run();
}

}  // namespace rt::site
