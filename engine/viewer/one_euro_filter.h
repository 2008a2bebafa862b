#pragma once
// The One-Euro filter (Casiez, Roussel, Vogel, CHI 2012) on a 3D point: a low-pass whose cutoff
// rises with speed, so a still head's jitter is smoothed hard while a moving head lags little.
#include <Eigen/Core>

namespace rt {

struct OneEuroParameters {
  // Tuned on a seated viewer (still with a centimetre of sway, then 12 cm leans over 0.8 s) at
  // 30 fps with 3 mm of noise per axis: halves the jitter while still, adds no error while moving.
  // Cutoff when still: 0.5 Hz averages ~0.3 s of frames.
  double min_cutoff_hz = 0.5;
  // Added cutoff per m/s of speed: at 0.2 m/s (a lean) the cutoff reaches 5.5 Hz, a lag of
  // ~30 ms, one frame.
  double speed_coefficient = 25.0;
  // Cutoff of the speed estimate itself, which is noisier than the position.
  double derivative_cutoff_hz = 1.0;
};

class OneEuroFilter {
 public:
  explicit OneEuroFilter(const OneEuroParameters& parameters = {});

  // The first value passes through; `dt_s` must be > 0 and finite (std::invalid_argument).
  Eigen::Vector3d update(const Eigen::Vector3d& value, double dt_s);
  // Starts again from `value` at rest.
  void reset(const Eigen::Vector3d& value);

  bool initialised() const { return initialised_; }
  const Eigen::Vector3d& value() const { return value_; }
  const Eigen::Vector3d& velocity() const { return velocity_; }

 private:
  OneEuroParameters parameters_;
  bool initialised_ = false;
  Eigen::Vector3d value_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity_ = Eigen::Vector3d::Zero();
};

}  // namespace rt
