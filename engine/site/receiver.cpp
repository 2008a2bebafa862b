#include "site/receiver.h"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>

#include <cmath>
#include <fstream>
#include <iostream>

#include "config/assets.h"
#include "pipeline/hand_renderer.h"
#include "pipeline/receiver_compositor.h"
#include "site/site_window.h"
#include "time/monotonic_clock.h"

namespace rt::site {
namespace {

// Remote skeletons kept to pose the hand from: a portrait is shown seconds after the moment it
// shows on a loaded lavapipe (up to 7 s in a demo's first frames, while the other processes
// start); twenty seconds at 50 Hz (about 1.5 MB) covers that.
constexpr size_t kSkeletonHistory = 1024;

// The gap limit is about how far the hand can move, so it counts in scene time: a scene played
// slower (--time-scale) stretches the sender's clock between the same two poses.
uint64_t max_skeleton_gap_us(double time_scale) {
  return uint64_t(std::llround(double(kMaxSkeletonGapUs) / std::max(time_scale, 1e-3)));
}

// While the link is down, a frame this often shows the user that the remote side is lost.
constexpr uint64_t kLinkLostFrameIntervalUs = 250'000;

}  // namespace

Receiver::Receiver(SiteCommon& common)
    : common_(common), remote_skeletons_(kSkeletonHistory, max_skeleton_gap_us(common.options.time_scale)) {}

void Receiver::on_skeleton(const net::SkeletonMessage& skeleton) {
  remote_skeletons_.add({skeleton.timestamp_us, skeleton.hands});
}

void Receiver::on_portrait(const net::PortraitMessage& portrait, uint64_t arrival_us) {
  portrait_network_.add(double(int64_t(arrival_us) - int64_t(portrait.capture_timestamp_us)) / 1000.0);
  last_portrait_arrival_us_ = arrival_us;
  portraits_.put({portrait, arrival_us});
}

void Receiver::stop() { portraits_.close(); }

void Receiver::display_loop() {
  // Declared first, so destroyed last: the receiver's Vulkan objects go while this holds the turn.
  std::unique_lock<session::FairMutex> final_turn(common_.gpu_turn, std::defer_lock);
  std::unique_ptr<pipeline::ReceiverCompositor> compositor;
  std::unique_ptr<pipeline::HandRenderer> hand;
  std::unique_ptr<vk::Image> portrait_depth;  // for appearance adaption; the color is the compositor's
  std::unique_ptr<SiteWindowDisplay> window;   // --display window or both
  vk::FrameGraph graph(*common_.context, "receiver frame");
  vk::FrameGraph hand_graph(*common_.context, "geometry hand");
  float hand_distance_m = NAN;
  {
    std::lock_guard turn(common_.gpu_turn);
    // A window's views show the hand's alpha: only then are the layers written.
    compositor = std::make_unique<pipeline::ReceiverCompositor>(*common_.context, common_.background,
                                                                common_.window != nullptr);
    compositor->add_to(graph, [&] { return hand_distance_m; });
    hand = std::make_unique<pipeline::HandRenderer>(*common_.context, config::assets_dir() / "hand", common_.width,
                                                    common_.height, common_.options.hand);
    hand->add_to(hand_graph);
    // The render goes to the compositor on the device: the frame never waits on a host round trip.
    hand_graph.add_image_copy("hand_color_to_compositor", hand->color(), compositor->hand_color);
    hand_graph.add_image_copy("hand_mask_to_compositor", hand->mask(), compositor->hand_mask);
    portrait_depth = std::make_unique<vk::Image>(
        *common_.context, vk::ImageDesc{"adaption portrait depth", common_.width, common_.height, PixelFormat::R32F});
    if (common_.window)
      window = std::make_unique<SiteWindowDisplay>(
          common_, ReceiverImages{compositor->portrait, compositor->hand_mask, *compositor->hand_alpha, compositor->hand_color,
                                  compositor->display});
  }
  vk::Image& portrait = compositor->portrait;
  cv::VideoWriter video;
  if (common_.write_frames)
    // At the pace the scene's frames came on the wall's clock: the video lasts as long as the
    // display showed it, slowed with the scene where it played slower than real time, so that the
    // sound heard meanwhile fits under it.
    video.open(common_.out / "site.mp4", cv::VideoWriter::fourcc('m', 'p', '4', 'v'),
               common_.scene.fps * common_.options.time_scale, cv::Size(int(common_.width), int(common_.height)));
  if (common_.write_frames && !video.isOpened()) common_.events->write("warning", monotonic_now_us(), {{"message", "OpenCV cannot write site.mp4 here"}});
  std::ofstream frames_log(common_.out / "frames.jsonl");
  const HostImage no_portrait(common_.width, common_.height, PixelFormat::RGBA32F);
  uint64_t last_shown_us = 0;
  uint64_t portraits_shown = 0;
  // The video shows what the screen showed, when it showed it: its slot n covers the wall's
  // [first + n / rate, first + (n + 1) / rate), and each shown frame stays in the slots until the
  // next one's display time. A frame shown within a slot already written waits for the next.
  const double video_rate = common_.scene.fps * common_.options.time_scale;
  uint64_t video_slots = 0;
  cv::Mat video_held;
  // A displayed frame: PNG, its slots of the MP4, a line of frames.jsonl.
  auto write_frame = [&](const cv::Mat& bgr, nlohmann::json entry) {
    const uint64_t display_index = frames_displayed_++;
    if (common_.write_frames) cv::imwrite((common_.out / "frames" / frame_name(display_index)).string(), bgr);
    if (video.isOpened()) {
      const uint64_t shown_us = entry["t_us"].get<uint64_t>();
      if (first_video_frame_us_ == 0) first_video_frame_us_ = shown_us;
      const uint64_t since_us = shown_us > first_video_frame_us_ ? shown_us - first_video_frame_us_ : 0;
      const uint64_t slot = uint64_t(double(since_us) * 1e-6 * video_rate);
      // Bounded by the run's length: the display ends with the scene, or 30 s after it.
      for (; !video_held.empty() && video_slots < slot; ++video_slots) video.write(video_held);
      if (video_slots <= slot) video.write(bgr), ++video_slots;
      video_held = bgr;
    }
    entry["display"] = display_index;
    frames_log << entry.dump() << "\n";
  };

  while (true) {
    std::optional<ReceivedPortrait> received = portraits_.wait_take(std::chrono::milliseconds(50));
    if (!received) {
      if (window && window->take_keys()) {
        session::UrgentTurn turn(common_.gpu_turn);
        window->refresh();
      }
      const uint64_t now = monotonic_now_us();
      const uint64_t quiet_since = std::max<uint64_t>(last_portrait_arrival_us_, common_.end_us);
      // Before the first portrait, the peer may still be starting up on a loaded machine: wait
      // longer for it than for the tail of a stream that has been flowing.
      const double linger_s = last_portrait_arrival_us_ ? common_.options.linger_s : std::max(common_.options.linger_s, 10.0);
      if (common_.sender_done && now > common_.end_us && now - quiet_since > uint64_t(linger_s * 1e6)) break;
      if (now > common_.end_us + 30'000'000) break;  // the peer is gone for good
      if (common_.stopping) break;
      // While the link is down the display keeps running and says so (after the scene's end, a
      // closing peer is the normal shutdown).
      if (now < common_.end_us && now - last_shown_us >= kLinkLostFrameIntervalUs &&
          common_.net->status().state != net::ConnectionState::Connected) {
        HostImage frame;
        {
          session::UrgentTurn turn(common_.gpu_turn);
          vk::upload(*common_.context, portrait, no_portrait);  // background only
          hand_distance_m = NAN;
          graph.run();
          frame = vk::download(*common_.context, compositor->display);
        }
        cv::Mat bgr = to_bgr8(frame);
        label_link_lost(bgr, common_.net->status().reason);
        ++link_lost_frames_;
        const uint64_t display_index = frames_displayed_;
        write_frame(bgr, {{"portrait_frame", nullptr}, {"t_us", now}, {"link_lost", true}});
        if (window) {  // the notice is drawn on the CPU: the screen shows it as the file does
          window->take_keys();
          session::UrgentTurn turn(common_.gpu_turn);
          vk::upload(*common_.context, compositor->display, from_bgr8(bgr));
          window->show_frame(display_index);
        }
        last_shown_us = now;
      }
      continue;
    }
    portrait_queue_wait_.add(double(int64_t(monotonic_now_us()) - int64_t(received->arrival_us)) / 1000.0);
    const net::PortraitMessage& message = received->message;
    if (message.width != common_.width || message.height != common_.height) {
      if (portraits_wrong_size_++ == 0)
        common_.events->write("error", monotonic_now_us(),
                      {{"message", "portrait is " + std::to_string(message.width) + "x" + std::to_string(message.height) +
                                       ", this site displays " + std::to_string(common_.width) + "x" + std::to_string(common_.height)}});
      continue;
    }
    // The remote hands at the moment the portrait shows (both on the sender's clock), posed in its
    // view. No skeleton near that moment, or one that cannot be posed, shows the portrait alone
    // rather than a hand where it no longer is.
    const HandsAtTime at = remote_skeletons_.at(message.capture_timestamp_us);
    const HandSkeleton* drawn = hand_nearest_screen(at.hands);
    if (at.stale()) ++frames_no_hand_skeleton_gap_;
    const size_t drawn_index = drawn ? size_t(drawn - at.hands.data()) : 0;
    bool with_hand = false, adapted = false, adapted_before_display = false;
    // The appearance adaption's state when the hand was drawn: a fit from this frame after the
    // display, below, shows only from the next frame on.
    nlohmann::json drawn_appearance;
    HostImage shown;
    uint64_t on_screen = 0;
    {
      const uint64_t asked_us = monotonic_now_us();
      session::UrgentTurn turn(common_.gpu_turn);
      display_turn_wait_.add(double(monotonic_now_us() - asked_us) / 1000.0);
      const SiteCapture::Scope capture = common_.capture->scope(SiteCapture::Stage::Receiver, portraits_shown++);
      if (drawn) {  // in the turn: a new template or shape uploads its mesh
        hand->set_pose(*drawn, portrait_camera(message));
        with_hand = hand->has_pose() && hand->pose_error().empty();
      }
      vk::upload(*common_.context, portrait, message.color);
      // Before its first fit the hand wears the template's skin: fitted from this very portrait
      // first, the first hand shown wears the user's (hand_renderer.h: awaits_first_fit).
      if (with_hand && hand->awaits_first_fit()) {
        vk::upload(*common_.context, *portrait_depth, message.depth);
        adapted = hand->adapt_appearance_from(portrait, *portrait_depth);
        adapted_before_display = true;
      }
      if (with_hand) {
        const uint64_t start = monotonic_now_us();
        hand_graph.run();
        hand_wall_.add(double(monotonic_now_us() - start) / 1000.0);
        ++hand_renders_done_;
        const hand::AppearanceStatus status = hand->appearance_status();
        drawn_appearance = {{"state", appearance_phase_name(status.phase)},
                            {"frames_fitted", status.frames_fitted},
                            {"provisional", status.provisional}};
      }
      hand_distance_m = with_hand ? float(hand->hand_distance_m()) : NAN;
      const uint64_t start = monotonic_now_us();
      graph.run();
      if (window) {
        window->take_keys();
        window->show_frame(frames_displayed_);
      }
      if (common_.write_frames) shown = vk::download(*common_.context, compositor->display);
      on_screen = monotonic_now_us();
      receiver_wall_.add(double(on_screen - start) / 1000.0);
    }
    // Appearance adaption (Eq. 3) compares this portrait with the hand posed for its moment in its
    // view, on every shown portrait where the cameras see the hand (beyond d_max, or closer
    // until a frame there has fitted, as adapt_appearance_from decides); the adapted texture is
    // what the next renders sample. The frame is on screen already: this waits its turn behind
    // the sender's work rather than ahead of it.
    if (with_hand && !adapted_before_display && hand->appearance_adaption_possible()) {
      std::lock_guard turn(common_.gpu_turn);
      vk::upload(*common_.context, *portrait_depth, message.depth);
      adapted = hand->adapt_appearance_from(portrait, *portrait_depth);
    }
    if (adapted) ++appearance_adaptions_;
    // Counted in displayed frames, not seconds: the fit goes stale by frames shown without one.
    hand->note_frame_displayed();
    for (const nlohmann::json& change : hand->take_appearance_events()) {
      common_.events->write("appearance", monotonic_now_us(), change);
      std::cerr << "site " << common_.name << ": appearance adaption " << change.value("change", std::string()) << ": "
                << change.value("describe", std::string()) << "\n";
    }
    {
      std::lock_guard lock(appearance_mutex_);
      appearance_status_ = hand->appearance_status();
      appearance_shading_ = hand->shading_fit().to_json();
    }
    last_shown_us = on_screen;
    portrait_on_screen_.add(double(int64_t(on_screen) - int64_t(message.capture_timestamp_us)) / 1000.0);
    std::optional<double> skeleton_gap_ms;
    if (with_hand) {
      ++frames_with_hand_;
      // From the moment the pose shows (the portrait's, or the held sample's) to the screen.
      hand_on_screen_.add(double(int64_t(on_screen) - int64_t(drawn->timestamp_us)) / 1000.0);
      skeleton_gap_ms = double(at.gap_us[drawn_index]) / 1000.0;
      skeleton_to_portrait_gap_.add(*skeleton_gap_ms);
    }
    const char* hand_pose = !with_hand ? (at.stale() ? "no skeleton near" : drawn ? "not posed" : "no hand")
                            : at.interpolated[drawn_index] ? "interpolated" : "held";
    write_frame(common_.write_frames ? to_bgr8(shown) : cv::Mat(),
                {{"portrait_frame", message.frame_index},
                 {"t_us", on_screen},
                 {"hand_pose", hand_pose},
                 {"skeleton_gap_ms", skeleton_gap_ms ? nlohmann::json(*skeleton_gap_ms) : nlohmann::json()},
                 {"nearest_skeleton_ms", at.nearest_sample_gap_us ? nlohmann::json(double(*at.nearest_sample_gap_us) / 1000.0)
                                                                  : nlohmann::json()},
                 {"appearance_fitted_from_this_frame", adapted},
                 {"drawn_hand_appearance", drawn_appearance},
                 {"hand_distance_m", std::isfinite(hand_distance_m) ? nlohmann::json(hand_distance_m) : nlohmann::json()}});
  }
  {
    std::lock_guard lock(appearance_mutex_);
    appearance_status_ = hand->appearance_status();
    appearance_shading_ = hand->shading_fit().to_json();
    // A receiver that never fitted the remote user's skin showed them in the template's: say so.
    if (appearance_status_.phase == hand::AppearancePhase::Waiting)
      common_.events->write("warning", monotonic_now_us(),
                            {{"message", "appearance adaption never fitted: " + appearance_status_.describe()}});
  }
  if (window) {
    std::lock_guard lock(appearance_mutex_);
    window_metrics_ = window->metrics();
  }
  common_.record_gpu_ms("receiver", graph);
  common_.record_gpu_ms("hand", hand_graph);
  if (hand->appearance_graph()) common_.record_gpu_ms("appearance", *hand->appearance_graph());
  final_turn.lock();
}

void Receiver::add_metrics(nlohmann::json& m, double wall_s) const {
  {
    std::lock_guard lock(appearance_mutex_);
    m["appearance"] = appearance_status_.to_json();
    m["appearance_shading"] = appearance_shading_;
  }
  {
    std::lock_guard lock(appearance_mutex_);
    if (!window_metrics_.is_null()) m["window"] = window_metrics_;
  }
  m["stage_wall_ms"]["hand_render"] = hand_wall_.to_json();
  m["stage_wall_ms"]["receiver_render_and_readback"] = receiver_wall_.to_json();
  m["stage_wall_ms"]["portrait_queue_wait"] = portrait_queue_wait_.to_json();
  m["stage_wall_ms"]["display_turn_wait"] = display_turn_wait_.to_json();
  m["latency_ms"]["capture_to_portrait_received"] = portrait_network_.to_json();
  m["latency_ms"]["capture_to_portrait_on_screen"] = portrait_on_screen_.to_json();
  m["latency_ms"]["skeleton_to_hand_on_screen"] = hand_on_screen_.to_json();
  m["latency_ms"]["skeleton_to_portrait_gap"] = skeleton_to_portrait_gap_.to_json();
  m["hand_timing"]["max_skeleton_gap_ms"] = double(remote_skeletons_.max_gap_us()) / 1000.0;
  m["fps"]["hand_renders"] = double(hand_renders_done_) / wall_s;
  m["fps"]["display"] = double(frames_displayed_) / wall_s;
  m["frames"]["displayed"] = frames_displayed_.load();
  m["frames"]["displayed_link_lost"] = link_lost_frames_.load();
  m["frames"]["dropped_before_display"] = portraits_.dropped();
  m["frames"]["portraits_wrong_size"] = portraits_wrong_size_.load();
  m["frames"]["with_mesh_hand"] = frames_with_hand_.load();
  m["frames"]["no_hand_skeleton_gap"] = frames_no_hand_skeleton_gap_.load();
  m["frames"]["appearance_adapted"] = appearance_adaptions_.load();
}

}  // namespace rt::site
