#include "site/receiver.h"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>

#include <cmath>
#include <fstream>
#include <thread>

#include "config/assets.h"
#include "image/image_crop.h"
#include "pipeline/hand_renderer.h"
#include "pipeline/receiver_compositor.h"
#include "sim/tracker_sim.h"
#include "time/monotonic_clock.h"

namespace rt::site {
namespace {

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

}  // namespace

// Two seconds of skeletons at 50 Hz.
Receiver::Receiver(SiteCommon& common) : common_(common), remote_skeletons_(100), hand_renders_(kHandRenderHistory) {}

void Receiver::on_skeleton(const net::SkeletonMessage& skeleton) {
  skeletons_to_draw_.put(skeleton);
  remote_skeletons_.add(skeleton.timestamp_us, skeleton);
}

void Receiver::on_portrait(const net::PortraitMessage& portrait, uint64_t arrival_us) {
  portrait_network_.add(double(int64_t(arrival_us) - int64_t(portrait.capture_timestamp_us)) / 1000.0);
  last_portrait_arrival_us_ = arrival_us;
  portraits_.put({portrait, arrival_us});
}

void Receiver::stop() { portraits_.close(); }

void Receiver::hand_loop() {
  // Declared first, so destroyed last: the hand's Vulkan objects go while this holds the turn.
  std::unique_lock<session::FairMutex> final_turn(common_.gpu_turn, std::defer_lock);
  vk::Image portrait(*common_.context, {"adaption portrait", common_.width, common_.height, PixelFormat::RGBA32F});
  vk::Image portrait_depth(*common_.context, {"adaption portrait depth", common_.width, common_.height, PixelFormat::R32F});
  pipeline::HandRenderer hand(*common_.context, config::assets_dir() / "hand", common_.width, common_.height,
                             common_.options.hand);
  vk::FrameGraph graph(*common_.context, "geometry hand");
  {
    std::lock_guard turn(common_.gpu_turn);
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
    HandRender render = cropped_hand_render(vk::download(*common_.context, hand.color()), vk::download(*common_.context, hand.mask()),
                                            float(hand.hand_distance_m()));
    hand_wall_.add(double(monotonic_now_us() - start) / 1000.0);
    ++hand_renders_done_;
    return render;
  };
  // One render per camera frame is all the display can use; more would only take GPU turns
  // from the image-based model (lavapipe has one GPU's worth of CPU for everything).
  const auto period = std::chrono::microseconds(
      std::max<int64_t>(sim::kTrackerPeriodUs, int64_t(1e6 / (common_.scene.fps * common_.options.time_scale))));
  auto next = std::chrono::steady_clock::now();
  while (!display_done_ && !common_.stopping) {
    // Appearance adaption (Eq. 3) compares a shown portrait with the hand posed at its capture
    // time, in its view; the adapted texture is what the next renders sample. Only where the
    // cameras see the hand well (beyond d_max), as adapt_appearance_from requires anyway.
    if (std::optional<ReceivedPortrait> shown = portraits_shown_.take()) {
      const net::PortraitMessage& message = shown->message;
      const auto skeleton = remote_skeletons_.closest(message.capture_timestamp_us);
      if (skeleton && pose(skeleton->second, portrait_camera(message)) && hand.appearance_adaption_possible()) {
        // Urgent like the display: the receiver's work is what the user waits for.
        session::UrgentTurn turn(common_.gpu_turn);
        hand_renders_.add(skeleton->first, render_in_turn());
        vk::upload(*common_.context, portrait, message.color);
        vk::upload(*common_.context, portrait_depth, message.depth);
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
      session::UrgentTurn turn(common_.gpu_turn);
      hand_renders_.add(skeleton->timestamp_us, render_in_turn());
    } else {
      hand_renders_.add(skeleton->timestamp_us, HandRender{});  // no hand near: the portrait alone
    }
    next += period;
    const auto now = std::chrono::steady_clock::now();
    if (next < now) next = now;  // fell behind: skip, do not burst
    std::this_thread::sleep_until(next);
  }
  common_.record_gpu_ms("hand", graph);
  if (hand.appearance_graph()) common_.record_gpu_ms("appearance", *hand.appearance_graph());
  final_turn.lock();
}

void Receiver::display_loop() {
  // Declared first, so destroyed last: the receiver's Vulkan objects go while this holds the turn.
  std::unique_lock<session::FairMutex> final_turn(common_.gpu_turn, std::defer_lock);
  std::unique_ptr<pipeline::ReceiverCompositor> compositor;
  vk::FrameGraph graph(*common_.context, "receiver frame");
  float hand_distance_m = NAN;
  {
    std::lock_guard turn(common_.gpu_turn);
    compositor = std::make_unique<pipeline::ReceiverCompositor>(*common_.context, common_.background);
    compositor->add_to(graph, [&] { return hand_distance_m; });
  }
  vk::Image& portrait = compositor->portrait;
  cv::VideoWriter video(common_.out / "site.mp4", cv::VideoWriter::fourcc('m', 'p', '4', 'v'), common_.scene.fps,
                        cv::Size(int(common_.width), int(common_.height)));
  if (!video.isOpened()) common_.events->write("warning", monotonic_now_us(), {{"message", "OpenCV cannot write site.mp4 here"}});
  std::ofstream frames_log(common_.out / "frames.jsonl");
  std::optional<uint64_t> last_video_frame;
  const HostImage no_portrait(common_.width, common_.height, PixelFormat::RGBA32F);
  uint64_t last_shown_us = 0;
  // A displayed frame: PNG, `video_repeat` frames of the MP4, a line of frames.jsonl.
  auto write_frame = [&](const cv::Mat& bgr, nlohmann::json entry, uint64_t video_repeat) {
    const uint64_t display_index = frames_displayed_++;
    cv::imwrite((common_.out / "frames" / frame_name(display_index)).string(), bgr);
    if (video.isOpened())
      for (uint64_t i = 0; i < video_repeat; ++i) video.write(bgr);
    entry["display"] = display_index;
    frames_log << entry.dump() << "\n";
  };

  while (true) {
    std::optional<ReceivedPortrait> received = portraits_.wait_take(std::chrono::milliseconds(50));
    if (!received) {
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
        write_frame(bgr, {{"portrait_frame", nullptr}, {"t_us", now}, {"link_lost", true}}, 1);
        last_shown_us = now;
      }
      continue;
    }
    const net::PortraitMessage& message = received->message;
    if (message.width != common_.width || message.height != common_.height) {
      if (portraits_wrong_size_++ == 0)
        common_.events->write("error", monotonic_now_us(),
                      {{"message", "portrait is " + std::to_string(message.width) + "x" + std::to_string(message.height) +
                                       ", this site displays " + std::to_string(common_.width) + "x" + std::to_string(common_.height)}});
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
      session::UrgentTurn turn(common_.gpu_turn);
      vk::upload(*common_.context, portrait, message.color);
      if (with_hand) {
        const PixelBox& box = hand->second.box;
        vk::upload(*common_.context, compositor->hand_color, paste_on_zero(hand->second.color, box.x, box.y, common_.width, common_.height));
        vk::upload(*common_.context, compositor->hand_mask, paste_on_zero(hand->second.mask, box.x, box.y, common_.width, common_.height));
      }
      hand_distance_m = with_hand ? hand->second.distance_m : NAN;
      const uint64_t start = monotonic_now_us();
      graph.run();
      shown = vk::download(*common_.context, compositor->display);
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
  common_.record_gpu_ms("receiver", graph);
  final_turn.lock();
}

void Receiver::add_metrics(nlohmann::json& m, double wall_s) const {
  m["stage_wall_ms"]["hand_render_and_readback"] = hand_wall_.to_json();
  m["stage_wall_ms"]["receiver_render_and_readback"] = receiver_wall_.to_json();
  m["latency_ms"]["capture_to_portrait_received"] = portrait_network_.to_json();
  m["latency_ms"]["capture_to_portrait_on_screen"] = portrait_on_screen_.to_json();
  m["latency_ms"]["skeleton_to_hand_on_screen"] = hand_on_screen_.to_json();
  m["latency_ms"]["hand_render_to_portrait_capture_gap"] = hand_to_portrait_gap_.to_json();
  m["fps"]["hand_renders"] = double(hand_renders_done_) / wall_s;
  m["fps"]["display"] = double(frames_displayed_) / wall_s;
  m["frames"]["displayed"] = frames_displayed_.load();
  m["frames"]["displayed_link_lost"] = link_lost_frames_.load();
  m["frames"]["dropped_before_display"] = portraits_.dropped();
  m["frames"]["portraits_wrong_size"] = portraits_wrong_size_.load();
}

}  // namespace rt::site
