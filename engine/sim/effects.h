#pragma once
// The imperfections a scene may ask for. Each is off unless the scene lists it, and an effect
// that is off is an empty std::optional: the code that applies it tests the optional once and
// pays nothing else. The CPU side (tracker_sim.h) applies the tracker effects; the per-pixel
// camera effects are parsed and validated here and applied by the GPU simulator.
#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include <map>
#include <optional>
#include <string>
#include <vector>

namespace rt::sim {

// Depth noise sigma(d) = sigma_at_1m_m * d^2 (the growth law of time-of-flight noise with
// distance; "quadratic" is the only law so far).
struct DepthNoise {
  enum class Growth { Quadratic };
  double sigma_at_1m_m = 0.002;
  Growth growth = Growth::Quadratic;
};
// Mixed depths at discontinuities: where neighbouring depths differ by more than
// edge_threshold_m, a pixel becomes a flying pixel with `probability`.
struct FlyingPixels {
  double edge_threshold_m = 0.05;
  double probability = 0.5;
};
// Depths nearer than min_range_m read as invalid (0), as a real camera's do.
struct NearCutoff {
  double min_range_m = 0.25;
};
// Skin reads too far on a time-of-flight camera (subsurface scattering): about +1 cm.
struct SkinDepthBias {
  double bias_m = 0.01;
};
struct CameraColor {
  double gain = 1.0;
  Eigen::Vector3d white_balance = Eigen::Vector3d::Ones();  // r, g, b multipliers
};
// Per-camera exposure and white balance; cameras not listed keep gain 1 and white balance 1.
struct ColorGain {
  std::map<std::string, CameraColor> cameras;
  CameraColor for_camera(const std::string& name) const;
};
// Depth shifted against color, in color pixels: a registration error.
struct Misregistration {
  double pixels_x = 0.0;
  double pixels_y = 0.0;
};
// Each camera frame's capture time scatters around its nominal time.
struct CameraTimingJitter {
  double sigma_ms = 2.0;
};
// Independent Gaussian noise on every reported joint position, per axis, in the tracker's space.
struct TrackerJitter {
  double sigma_mm = 1.0;
};
// A frame stamped t reports the hand as it was at t - ms.
struct TrackerLatency {
  double ms = 20.0;
};
// Tracking lost for bursts of frames: `probability` is the long-run fraction of frames without
// hands, burst lengths are geometric with mean mean_length_frames.
struct TrackerDropouts {
  double probability = 0.05;
  double mean_length_frames = 5.0;
};

// The room's echo: what the site's loudspeaker plays comes back into its microphone (the audio
// devices' simulated room, devices/audio/simulated_room.h).
struct RoomEcho {
  double delay_ms = 50.0;
  double gain_db = -6.0;
  double reverb_ms = 60.0;  // reflections after the direct path, spread over this long
  double reverb_db = -18.0;  // the last reflection, below the direct path
};

// A marker for sound against picture, as film's clapperboard: at each time the user claps (a click
// in the simulated microphone, placed at the sample captured then) and their shirt flashes white
// for flash_ms in the cameras. The users say nothing else, so that the click stands alone.
struct AvMarker {
  std::vector<double> times_s;
  double flash_ms = 200.0;
  // Whether the shirt is flashing at scene time t_s.
  bool flashing_at(double t_s) const;
};

struct TrackerEffects {
  std::optional<TrackerJitter> jitter;
  std::optional<TrackerLatency> latency;
  std::optional<TrackerDropouts> dropouts;
};

struct Effects {
  std::optional<DepthNoise> depth_noise;
  std::optional<FlyingPixels> flying_pixels;
  std::optional<NearCutoff> near_cutoff;
  std::optional<SkinDepthBias> skin_depth_bias;
  std::optional<ColorGain> color_gain;
  std::optional<Misregistration> misregistration;
  std::optional<CameraTimingJitter> camera_timing_jitter;
  TrackerEffects tracker;  // tracker_jitter, tracker_latency, tracker_dropouts
  std::optional<RoomEcho> room_echo;
  std::optional<AvMarker> av_marker;

  bool any() const;
};

const std::vector<std::string>& effect_names();

// JSON: {"depth_noise": {"sigma_at_1m_m": 0.002, "growth": "quadratic"}, "tracker_jitter":
// {"sigma_mm": 1.5}, ...}; every parameter is required. color_gain names cameras, which must
// be among `camera_names`. Errors start with `where` and name the effect and the field.
Effects effects_from_json(const nlohmann::json& json, const std::string& where,
                          const std::vector<std::string>& camera_names);
nlohmann::json effects_to_json(const Effects& effects);

}  // namespace rt::sim
