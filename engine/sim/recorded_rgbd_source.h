#pragma once
// A recorded sequence of a site's RGBD frames, whatever its format: RemoteTouch's PNG folders
// (recording.h) or one k4a recording per camera (devices/camera/k4a_site_recordings.h). Every
// frame's time is known before any image is read, so that a replay can pace itself and skip
// what it cannot keep up with.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "sim/rgbd_source.h"
#include "sim/site_description.h"

namespace rt::sim {

class RecordedRgbdSource : public RgbdSource {
 public:
  struct RecordedIntrinsics {
    CameraIntrinsics color, depth;
    // Where the colour camera is from the depth camera; a real device's two lenses are apart.
    Eigen::Isometry3d color_from_depth = Eigen::Isometry3d::Identity();
  };
  // Where the cameras stand, as calibrated.
  virtual const SiteDescription& site() const = 0;
  // Of camera k's images as recorded (the size they have).
  virtual const std::vector<RecordedIntrinsics>& recorded_intrinsics() const = 0;
  virtual size_t frame_count() const = 0;
  // Of the i-th frame, without reading its images.
  virtual uint64_t frame_index(size_t i) const = 0;
  virtual uint64_t frame_timestamp_us(size_t i) const = 0;
  // The next next_frame() gives the i-th frame (i == frame_count(): the end).
  virtual void seek(size_t i) = 0;
};

}  // namespace rt::sim
