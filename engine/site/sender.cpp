#include "site/sender.h"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <stdexcept>
#include <thread>

#include "camera/site_camera_sources.h"
#include "geometry/target_view.h"
#include "ibr/camera_selection.h"
#include "image/image_io.h"
#include "site/site_display.h"
#include "site/site_metrics.h"
#include "sim/face.h"
#include "sim/tracker_sim.h"
#include "sim/tracker_space.h"
#include "time/monotonic_clock.h"

namespace rt::site {

namespace {

// Long enough for a service on this machine or the local network; a missing one is reported
// before the site waits for its peer.
constexpr std::chrono::milliseconds kLeapConnectTimeout{3000};
// A live frame older than this is a service that stalled: no hands rather than frozen ones.
constexpr uint64_t kLeapFrameMaxAgeUs = 5 * sim::kTrackerPeriodUs;

}  // namespace

Sender::Sender(SiteCommon& common, SiteTouchLoop& touch) : common_(common), touch_(touch) {
  const SiteRunOptions& options = common_.options;
  pipeline::IbrSettings settings = options.ibr;
  settings.width = common_.width;
  settings.height = common_.height;
  std::vector<passes::IbrCameraModel> cameras;
  if (!options.replay.empty()) {
    // The recording stands for this site's devices: its calibration is the site, its frames and
    // its times are the scene's.
    replay_ = std::make_unique<SiteReplay>(options.replay, options.frames_given ? options.run.frames : 0, settings.views);
    common_.scene.sites[options.site == Site::A ? 0 : 1].site = replay_->site();
    common_.scene.frame_count = uint32_t(replay_->frame_count());
    common_.scene.fps = replay_->pacing().fps(common_.scene.fps);
    registration_ = std::make_unique<pipeline::RecordedDepthRegistration>(*common_.context, replay_->recorded());
    cameras = registration_->models(replay_->cameras());
    std::cerr << "site " << common_.name << ": replaying " << replay_->frame_count() << " frames of "
              << options.replay.string() << " (" << common_.scene.duration_s() << " s of scene time)"
              << (options.resolution_scale > 0 ? "; --resolution-scale does not apply to a replay" : "") << "\n";
    if (!replay_->has_tracker() && !leap_tracker_url(options.tracker)) {
      const std::string why = "'" + options.replay.string() + "' has no tracker.jsonl (the hand tracker's recording; "
                              "`record` and the vendor's recorder write none): no tracked hands are sent, so the other "
                              "site shows no hand mesh and no touch is detected; --tracker leap tracks the hands live";
      std::cerr << "site " << common_.name << ": " << why << "\n";
      common_.events->write("warning", monotonic_now_us(), {{"message", why}});
    }
  } else if (camera::site_source_kind(common_.site(), "'" + common_.scene.at(options.site).site_file.string() + "'") !=
             camera::CameraSourceKind::simulated) {
    cameras = open_live_site(settings.views);
  } else {
    const uint32_t truth_width = options.write_truth ? common_.width : 0;
    const uint32_t truth_height = options.write_truth ? common_.height : 0;
    simulator_ = std::make_unique<pipeline::SiteSimulator>(*common_.context, common_.scene, options.site, truth_width,
                                                           truth_height);
    cameras = simulator_->renderer().camera_models();
    if (options.write_truth) {
      limb_truth_ = std::make_unique<pipeline::LimbTruthRenderer>(*common_.context, *simulator_->renderer().target_view());
      truth_regions_ = std::make_unique<TruthRegionWriter>(common_.out / "truth");
    }
  }
  if (registration_ && registration_->registered_count())
    std::cerr << "site " << common_.name << ": " << registration_->registered_count() << " of " << cameras.size()
              << " cameras have their depth registered into their colour image\n";
  if (const std::optional<std::string> url = leap_tracker_url(options.tracker)) {
    devices::LeapServiceTracker::Options leap_options;
    leap_options.url = *url;
    leap_ = std::make_unique<devices::LeapServiceTracker>(leap_options);
    leap_->wait_connected(kLeapConnectTimeout);
    std::cerr << "site " << common_.name << ": tracker: the Leap service at " << leap_->url().text() << "\n";
  }
  ibr_ = std::make_unique<pipeline::IbrRenderer>(*common_.context, cameras, settings);
  for (const auto& camera : common_.site().cameras) camera_positions_.push_back(camera.color_camera().position_in_site());

  // The eye sent to the peer: the seat's head position until the cameras find the viewer's eyes
  // (or for good, where the scene asks for the seat).
  std::vector<Camera> color_cameras, depth_cameras;
  for (const auto& camera : cameras) {
    color_cameras.push_back(camera.color);
    depth_cameras.push_back(camera.depth);
  }
  EyeSearchOptions eye_options;
  if (common_.scene.viewpoint == sim::ViewpointSource::Seat) eye_options.use_seat_because = "the scene asks for the seat";
  eye_finder_ = std::make_unique<ViewerEyeFinder>(
      color_cameras, common_.site().seat.head_centre_m, eye_options, [this](const std::string& source) {
        // The terminal gets the reason's first clause; the event log keeps it whole (per camera).
        const size_t open = source.find('(');
        const size_t detail = open == std::string::npos ? open : source.find(": ", open);
        std::cerr << "site " << common_.name << ": eye: "
                  << (detail == std::string::npos ? source : source.substr(0, detail) + "; the reasons are in events.jsonl)")
                  << "\n";
        common_.events->write("eye_source", monotonic_now_us(), {{"source", source}});
      },
      depth_cameras);
  if (simulator_) look_for_eyes_before_the_call();
}

std::vector<passes::IbrCameraModel> Sender::open_live_site(size_t cameras_needed) {
  const SiteRunOptions& options = common_.options;
  sim::SiteSetup& setup = common_.scene.sites[options.site == Site::A ? 0 : 1];
  const std::string where = "'" + setup.site_file.string() + "'";
  // A site's recordings are a folder with their tracker: --replay plays them, paced by their
  // times, which a site file's cameras cannot give.
  if (camera::site_source_kind(setup.site, where) == camera::CameraSourceKind::k4a_recording)
    throw std::runtime_error(where + " names k4a recordings as its cameras: play them with --replay FOLDER (the folder "
                             "of a site.json beside the recordings), or give the cameras \"source\": \"k4a\" to run them live");
  if (setup.site.cameras.size() < cameras_needed)
    throw std::runtime_error(where + " has " + std::to_string(setup.site.cameras.size()) +
                             " cameras; the image-based model uses " + std::to_string(cameras_needed) + " (--views)");
  live_ = std::make_unique<camera::k4a::LiveSite>(setup.site, camera::live_site_settings(setup.site, where));
  setup.site = live_->site();  // each camera's lenses at its modes, from its factory calibration
  registration_ = std::make_unique<pipeline::RecordedDepthRegistration>(*common_.context, live_->intrinsics());
  // A live call lasts until it is stopped (Ctrl-C, Esc, the other site), a day at most.
  if (!options.frames_given) common_.scene.frame_count = uint32_t(std::lround(common_.scene.fps * 24 * 3600));
  std::cerr << "site " << common_.name << ": " << live_->infos().size() << " live k4a cameras from " << where << " ("
            << live_->infos().front().fps << " fps"
            << (options.frames_given ? ", " + std::to_string(common_.scene.frame_count) + " scene frames" : ", until stopped")
            << ")" << (options.resolution_scale > 0 ? "; --resolution-scale does not apply to live cameras" : "") << "\n";
  if (!leap_tracker_url(options.tracker))
    std::cerr << "site " << common_.name << ": the hands sent are the scene's simulated ones; --tracker leap tracks "
                 "this site's user\n";
  return registration_->models(device_camera_models(live_->site(), live_->intrinsics()));
}

void Sender::register_depth(sim::RgbdFrame& frame) {
  if (!registration_->registered_count()) return;
  std::lock_guard turn(common_.gpu_turn);
  registration_->apply(frame.cameras);
  ++frames_registered_;
}

void Sender::look_for_eyes_before_the_call() {
  // The paper's viewpoint is computed once, as the call starts, from a viewer sitting still. The
  // simulated user sits at the scene's first pose until the scene clock starts (at connection),
  // then moves at once; on a slow device the capture during the call spans seconds of scene time
  // per 15 frames, with the user leaning in. So the cameras watch the waiting user first, as a
  // real site's cameras run before its call connects. A bounded wait: max_frames frame sets.
  std::lock_guard turn(common_.gpu_turn);
  simulator_->seek(0);
  std::optional<sim::RgbdFrame> waiting = simulator_->next_frame();
  simulator_->seek(0);
  if (!waiting) return;
  for (int tries = 0; !eye_finder_->decided() && tries < 20000 && monotonic_now_us() < common_.eye_search_deadline_us &&
                     !stop_signal_received();
       ++tries) {
    if (eye_finder_->wants_frame()) eye_finder_->offer(monotonic_now_us(), waiting->cameras);
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
}

void Sender::set_remote_eye(const Eigen::Vector3d& eye) {
  std::lock_guard lock(eye_mutex_);
  remote_eye_ = eye;
}

void Sender::stop() { captured_.close(); }

std::optional<HostImage> Sender::ground_truth(uint64_t index, bool& told_no_truth) {
  // The recording's ground truth is the view from the remote eye of the scene it was made in
  // (sim::truth_viewer_eye).
  std::optional<HostImage> recorded = replay_->ground_truth(index);
  if (recorded && recorded->width == common_.width && recorded->height == common_.height && recorded->channels() == 4)
    return recorded;
  if (!told_no_truth) {
    told_no_truth = true;
    const std::string why = recorded ? "its gt/ target view is " + std::to_string(recorded->width) + "x" +
                                           std::to_string(recorded->height) + ", not the display's " +
                                           std::to_string(common_.width) + "x" + std::to_string(common_.height)
                                     : "it has no gt/ target view for frame " + std::to_string(index);
    common_.events->write("warning", monotonic_now_us(), {{"message", "no ground truth from the recording: " + why}});
  }
  return std::nullopt;
}

void Sender::capture_loop() {
  const double fps = common_.scene.fps;
  const bool write_truth = common_.options.write_truth;
  uint64_t last_index = UINT64_MAX;
  bool told_no_truth = false;
  while (!common_.stopping) {
    const uint64_t now = monotonic_now_us();
    // The cameras' frame due now: the simulator renders the scene's frame of this moment, a replay
    // takes the newest recorded frame whose time has come; either skips the frames it missed.
    std::optional<uint64_t> due;
    double next_s = 0;  // when the frame after `last_index` is due
    if (live_) {
      // The devices pace a live site: each set comes when they give it.
      if (common_.scene_time_s(now) >= common_.scene.duration_s()) break;
      due = last_index == UINT64_MAX ? 0 : last_index + 1;
    } else if (replay_) {
      if (const auto i = replay_->pacing().due_at(common_.scene_time_s(now))) due = *i;
      if (due && *due == last_index && last_index + 1 >= replay_->frame_count()) break;
      next_s = replay_->pacing().time_s(due && *due == last_index ? last_index + 1 : 0);
    } else {
      due = uint64_t(std::floor(common_.scene_time_s(now) * fps));
      if (*due >= common_.scene.frame_count) break;
      next_s = double(*due + 1) / fps;
    }
    if (!due || *due == last_index) {  // wait for the cameras' next frame
      const uint64_t due_us = common_.epoch_us + uint64_t(next_s / common_.options.time_scale * 1e6);
      std::this_thread::sleep_for(std::chrono::microseconds(due_us > now ? due_us - now : 0));
      continue;
    }
    uint64_t index = *due;
    CapturedFrame captured;
    HostImage truth;
    std::optional<pipeline::LimbTruth> limb;
    if (live_) {
      std::optional<sim::RgbdFrame> frame = live_->next_frame();  // waits for the devices: no GPU turn
      if (!frame) {
        std::cerr << "site " << common_.name << ": every live camera has stopped giving captures\n";
        common_.events->write("warning", monotonic_now_us(), {{"message", "every live camera has stopped giving captures"}});
        break;
      }
      captured.frame = std::move(*frame);
      // Taken as the devices gave it, which is when the set is complete.
      captured.scene_time_s = common_.scene_time_s(monotonic_now_us());
      register_depth(captured.frame);
    } else if (replay_) {
      captured.frame = replay_->read(index);  // files: no GPU turn
      register_depth(captured.frame);
      captured.scene_time_s = replay_->pacing().time_s(index);
      if (write_truth)
        if (std::optional<HostImage> recorded = ground_truth(index, told_no_truth)) truth = std::move(*recorded);
    } else {
      std::lock_guard turn(common_.gpu_turn);
      const uint64_t start = monotonic_now_us();
      // The turn may have come only after the image-based model's: the cameras show the moment
      // the simulator renders, not the one when this loop asked for the turn (an older frame
      // would only add its wait to the latency).
      index = std::max(index, std::min<uint64_t>(uint64_t(std::floor(common_.scene_time_s(start) * fps)), common_.scene.frame_count - 1));
      simulator_->seek(index);
      std::optional<sim::RgbdFrame> frame = simulator_->next_frame();
      if (!frame) break;
      captured.frame = std::move(*frame);
      captured.scene_time_s = double(index) / fps;
      // The eye this site sends now, against where its user's eyes truly are in this frame.
      eye_error_.add(eye_finder_->eye(), sim::true_eyes(simulator_->last_pose()).midpoint());
      simulator_wall_.add(double(monotonic_now_us() - start) / 1000.0);
    }
    last_index = index;
    last_scene_frame_ = index;
    captured.index = index;
    // Stamped with the moment the images show, as a camera stamps its exposure, not when the
    // simulator or the files had them ready (hundreds of milliseconds later on lavapipe): the
    // receiver poses the remote hand for this moment, from skeletons stamped when tracked.
    captured.capture_us = common_.wall_us_at_scene_time(captured.scene_time_s);
    // The viewer's eyes are looked for in the first frames, on the finder's own thread.
    if (eye_finder_->wants_frame()) eye_finder_->offer(captured.capture_us, captured.frame.cameras);
    ++frames_captured_;
    captured_.put(std::move(captured));
    // The ground truth is for the evaluation, not the call: measured after the frame has gone to
    // the image-based model, so that it does not wait for it. Only this loop renders the
    // simulator, so its target view still holds this frame.
    if (write_truth && simulator_) {
      std::lock_guard turn(common_.gpu_turn);
      truth = simulator_->renderer().target_color();
      limb = limb_truth_->measure(simulator_->last_pose(), common_.scene.at(common_.options.site).user, truth,
                                  simulator_->renderer().target_depth_m(), simulator_->renderer().target_part());
    }
    if (!truth.texels.empty()) {
      write_image(common_.out / "truth" / frame_name(index), truth_over_background(truth, common_.background));
      if (limb) truth_regions_->write(index, limb->region, limb->distance_m, limb->phase);
      ++truth_frames_;
    }
  }
  captured_.close();
}

const vk::FrameGraph& Sender::ibr_graph() const { return ibr_->graph(); }

void Sender::ibr_loop() {
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
    const Camera target = target_view_camera(*eye, common_.site().screen, common_.width, common_.height);
    // The cameras opposite the hand the tracker saw reaching at that moment (no ground truth here).
    const std::vector<HandSkeleton> hands = tracked_hands_.closest(captured->scene_time_s).value_or(std::vector<HandSkeleton>{});
    const auto selection = ibr::select_cameras(camera_positions_, touching_side(hands), ibr_->settings().views);
    net::PortraitMessage message;
    {
      std::lock_guard turn(common_.gpu_turn);
      const SiteCapture::Scope capture = common_.capture->scope(SiteCapture::Stage::Sender, portraits_rendered_++);
      const uint64_t start = monotonic_now_us();
      ibr_->render(captured->frame.cameras, selection, target);
      message.color = vk::download(*common_.context, ibr_->portrait());
      message.depth = vk::download(*common_.context, ibr_->portrait_depth());
      ibr_wall_.add(double(monotonic_now_us() - start) / 1000.0);
    }
    message.frame_index = captured->index;
    message.capture_timestamp_us = captured->capture_us;
    message.width = common_.width;
    message.height = common_.height;
    message.fx = target.intrinsics.fx;
    message.fy = target.intrinsics.fy;
    message.cx = target.intrinsics.cx;
    message.cy = target.intrinsics.cy;
    message.camera_from_site = target.camera_from_site.matrix();
    common_.net->send(message);  // encodes here, on this thread
    ++portraits_sent_;
    capture_to_sent_.add(double(monotonic_now_us() - captured->capture_us) / 1000.0);
  }
  common_.sender_done = true;
}

void Sender::tracker_loop() {
  const sim::SiteDescription& site = common_.site();
  PacedHandTracker tracker =
      replay_ ? PacedHandTracker(replay_->tracker(), site.tracker, replay_->origin_us())
              : PacedHandTracker(std::make_unique<sim::SimulatedHandTracker>(
                                     sim::make_simulated_tracker(common_.scene, common_.options.site)),
                                 site.tracker, 0);
  devices::LeapState leap_state = devices::LeapState::Connected;  // wait_connected saw it so
  std::optional<Eigen::Vector3d> sent_eye;
  auto next = std::chrono::steady_clock::now();
  for (uint64_t tick = 0; !common_.stopping; ++tick) {
    const uint64_t now = monotonic_now_us();
    // The paper computes the viewpoint once; sent again every half second so that a peer that
    // reconnects gets it too, and at once when the cameras' eye replaces the seat's.
    const Eigen::Vector3d eye = eye_finder_->eye();
    if (tick % 25 == 0 || !sent_eye || *sent_eye != eye) {
      common_.net->send(net::EyeMessage{now, eye, true});
      sent_eye = eye;
    }
    std::vector<HandSkeleton> hands;
    if (leap_) {
      const devices::LeapServiceStatus status = leap_->status();
      if (status.state != leap_state) {
        leap_state = status.state;
        std::cerr << "site " << common_.name << ": tracker: " << devices::leap_state_name(leap_state)
                  << (leap_state == devices::LeapState::Connected ? std::string() : ": " + status.last_error) << "\n";
        common_.events->write("tracker", now, status.to_json());
      }
      const auto newest = leap_->newest();
      if (newest && now - newest->received_us <= kLeapFrameMaxAgeUs) {
        hands = sim::skeletons_in_site(newest->frame, site.tracker);
        tracked_hands_.add(common_.scene_time_s(now), hands);
        for (auto& hand : hands) hand.timestamp_us = now;
      }
    } else if (const auto tracked = tracker.at(common_.scene_time_s(now))) {
      tracked_hands_.add(tracked->time_s, tracked->hands);
      hands = tracked->hands;
      // Stamped when the tracker saw them on the scene clock, not when this tick picked them up:
      // a frame stands for several ticks where the scene plays slowly, and the contact's
      // prediction fits the hand's motion against these times.
      const uint64_t captured_us = std::min(now, common_.wall_us_at_scene_time(tracked->time_s));
      for (auto& hand : hands) hand.timestamp_us = captured_us;
    }
    touch_.set_local_hands(hands);
    common_.net->send(net::SkeletonMessage{now, hands});
    ++tracker_ticks_;
    next += std::chrono::microseconds(sim::kTrackerPeriodUs);
    std::this_thread::sleep_until(next);
  }
}

void Sender::add_metrics(nlohmann::json& m, double wall_s) const {
  const net::NetCounters counters = common_.net->counters();
  m["inputs"] = replay_ ? "replay of " + replay_->dir().string()
                 : live_ ? "live k4a cameras of " + common_.scene.at(common_.options.site).site_file.string()
                         : std::string("simulated scene");
  if (live_) m["live_cameras"] = {{"cameras", live_->infos().size()}, {"skipped_captures", live_->skipped_captures()}};
  if (registration_) {
    m["depth_registered_cameras"] = registration_->registered_count();
    m["frames"]["depth_registered"] = frames_registered_.load();
  }
  m["eye_source"] = eye_finder_->source();
  m["eye"] = {eye_finder_->eye().x(), eye_finder_->eye().y(), eye_finder_->eye().z()};
  m["viewpoint"] = eye_finder_->to_json();
  m["viewpoint"]["scene_asks_for"] = common_.scene.viewpoint == sim::ViewpointSource::Seat ? "seat" : "cameras";
  // A recording holds no true eye to measure against.
  m["viewpoint"]["error_against_true_eye"] = simulator_ ? eye_error_.to_json() : nlohmann::json();
  if (simulator_) m["gpu_ms"]["simulator"] = timings_json(simulator_->renderer().graph());
  m["gpu_ms"]["ibr"] = timings_json(ibr_->graph());
  m["stage_wall_ms"]["simulator_render_and_readback"] = simulator_wall_.to_json();
  m["stage_wall_ms"]["ibr_render_and_readback"] = ibr_wall_.to_json();
  m["latency_ms"]["capture_to_portrait_sent"] = capture_to_sent_.to_json();
  m["fps"]["capture"] = double(frames_captured_) / wall_s;
  m["fps"]["portraits_sent"] = double(portraits_sent_) / wall_s;
  m["fps"]["tracker"] = double(tracker_ticks_) / wall_s;
  if (leap_) {
    const devices::LeapServiceStatus status = leap_->status();
    m["tracker"] = status.to_json();
    m["tracker"]["source"] = "the Leap service at " + leap_->url().text();
  } else {
    m["tracker"] = {{"source", !replay_                 ? "simulated from the scene"
                               : replay_->has_tracker() ? "the recording's tracker.jsonl"
                                                        : "none: the recording has no tracker.jsonl"}};
  }
  const uint64_t scene_frames = common_.scene.frame_count;
  m["frames"]["captured"] = frames_captured_.load();
  m["frames"]["portraits_sent"] = portraits_sent_.load();
  m["frames"]["dropped_before_ibr"] = captured_.dropped();
  m["frames"]["dropped_without_remote_eye"] = frames_without_eye_.load();
  m["frames"]["portraits_stale_on_wire_out"] =
      counters.stale_dropped_out[net::message_type_index(net::MessageType::Portrait)];
  m["frames"]["ground_truth_written"] = truth_frames_.load();
  // Live cameras give what they give: there is no scene frame to miss.
  m["frames"]["scene_frames_not_captured"] =
      live_ ? nlohmann::json() : nlohmann::json(scene_frames - std::min<uint64_t>(scene_frames, frames_captured_));
}

}  // namespace rt::site
