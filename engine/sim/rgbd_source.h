#pragma once
// A site's RGBD cameras as a device: every call gives the next frame of all cameras. Backends:
// the simulator (engine/app/simulated_rgbd.h, rendered by the engine) and replay of a recording
// (recording.h), so that a real capture converted to the recording format goes through the
// same code. Live cameras come later.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "image/host_image.h"

namespace rt::sim {

struct RgbdImage {
  std::string camera;          // the camera's name in the site description
  uint64_t timestamp_us = 0;   // capture time of this camera's image (monotonic clock)
  HostImage color;            // rgba8
  HostImage depth_mm;          // r16ui, 0 = invalid
};

struct RgbdFrame {
  uint64_t index = 0;
  uint64_t timestamp_us = 0;  // nominal frame time
  std::vector<RgbdImage> cameras;
};

class RgbdSource {
 public:
  virtual ~RgbdSource() = default;
  // Empty at the end of the sequence.
  virtual std::optional<RgbdFrame> next_frame() = 0;
};

}  // namespace rt::sim
