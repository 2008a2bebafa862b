#pragma once
// The eye a site sends to its peer (paper, "Viewpoint Computation"): the viewer's eyes found in
// the color images of several cameras, triangulated, their midpoint computed once at the start
// (viewer/initial_viewpoint.h). Until that succeeds, and for good if it does not within a bounded
// number of frames, the site description's seat head position stands in, and the site says so.
#include <Eigen/Core>

#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "geometry/camera.h"
#include "session/mailbox.h"
#include "sim/rgbd_source.h"
#include "viewer/initial_viewpoint.h"

namespace rt::site {

struct EyeSearchOptions {
  InitialViewpointOptions viewpoint;
  // Frame sets examined before giving up: twice what the estimate needs, so that a few frames
  // without eyes (a blink, a glance away) do not lose the cameras' eye.
  size_t max_frames = 30;
  // Not empty: no search at all, the seat stands from the start and this says why (a scene that
  // asks for the seat).
  std::string use_seat_because;
};

// The decision alone, frame by frame (no images, no threads): tested on its own.
class EyeSearch {
 public:
  enum class State { Searching, Found, GaveUp };
  explicit EyeSearch(const EyeSearchOptions& options = {});

  State add(uint64_t timestamp_us, const EyePair& frame);
  // Ends the search without a result (the detector cannot run here); `reason` says why.
  void give_up(const std::string& reason);
  State state() const { return state_; }
  size_t frames() const { return frames_; }
  size_t frames_with_eyes() const { return frames_with_eyes_; }
  // The cameras' eye once Found; else `seat`.
  Eigen::Vector3d eye_or(const Eigen::Vector3d& seat) const { return state_ == State::Found ? eye_ : seat; }
  // For the log and metrics.json: "cameras (15 frames, spread 2.1 mm)", "seat (no face found in
  // 30 frames: ...)", or "seat (searching: ...)" while undecided.
  std::string source() const;

 private:
  EyeSearchOptions options_;
  InitialViewpointEstimator estimator_;
  State state_ = State::Searching;
  size_t frames_ = 0, frames_with_eyes_ = 0;
  std::string last_miss_;  // the last frame's reason, while no frame had eyes
  std::string reason_;     // why it gave up
  Eigen::Vector3d eye_ = Eigen::Vector3d::Zero();
  double spread_m_ = 0.0;
};

// Runs the eye detector (CPU work, OpenCV's Haar cascades) on its own thread over the frames the
// capture offers while the search lasts, so that neither the capture nor the GPU waits for it.
class ViewerEyeFinder {
 public:
  // `cameras`: the color cameras as the images come (intrinsics at the images' size), in the
  // frames' camera order; `depth_cameras` the same for the depth images (empty: color only, two
  // views must see the eyes; else one view with depth will do: viewer/eye_depth.h).
  // `on_decided` is called once, from the finder's thread, with source().
  ViewerEyeFinder(std::vector<Camera> cameras, const Eigen::Vector3d& seat_eye, const EyeSearchOptions& options,
                  std::function<void(const std::string&)> on_decided, std::vector<Camera> depth_cameras = {});
  ~ViewerEyeFinder();
  ViewerEyeFinder(const ViewerEyeFinder&) = delete;
  ViewerEyeFinder& operator=(const ViewerEyeFinder&) = delete;

  // True while the search goes on and the finder is free for a frame: the capture copies the
  // color images only then.
  bool wants_frame() const;
  // Copies the color images (rgba8, one per camera in order), and the depth images when the
  // finder has depth cameras.
  void offer(uint64_t timestamp_us, const std::vector<sim::RgbdImage>& images);
  Eigen::Vector3d eye() const;
  std::string source() const;
  bool decided() const;
  // For metrics.json: "source" ("cameras" or "seat"), "describe" (source()), "position_m",
  // "frames_examined", "frames_with_eyes" and "fraction_with_eyes" (null before any frame).
  nlohmann::json to_json() const;

 private:
  struct Offered {
    uint64_t timestamp_us = 0;
    std::vector<HostImage> color;
    std::vector<HostImage> depth_mm;
  };
  void run();

  std::vector<Camera> cameras_;
  std::vector<Camera> depth_cameras_;
  Eigen::Vector3d seat_eye_;
  std::function<void(const std::string&)> on_decided_;
  session::Mailbox<Offered> frames_;
  mutable std::mutex mutex_;
  EyeSearch search_;
  bool busy_ = false;  // a frame is offered and not yet done
  std::thread thread_;
};

// The distance of the eye a site uses from its user's true eye (the simulator's), frame by frame:
// what the viewpoint computation achieves. Thread-safe.
class EyeErrorStats {
 public:
  void add(const Eigen::Vector3d& used, const Eigen::Vector3d& truth);
  // {"frames", "first_frame_mm" (the call's first frame, before the user moves), "median_mm",
  // "p95_mm", "max_mm", "mean_offset_mm" (used - true, site axes)}; nulls when empty.
  nlohmann::json to_json() const;

 private:
  mutable std::mutex mutex_;
  std::vector<double> errors_mm_;
  Eigen::Vector3d offset_sum_mm_ = Eigen::Vector3d::Zero();
};

}  // namespace rt::site
