#pragma once
// A recorded site, whatever wrote it: RemoteTouch's recording format (calibration.json,
// frames.jsonl and PNGs, sim/recording.h) or k4a recordings beside a site.json
// (k4a_site_recordings.h). `site --replay`, `demo --replay-a/-b` and `eval ibr --cameras-from`
// open both through this.
#include <filesystem>
#include <memory>
#include <string>

#include "sim/recorded_rgbd_source.h"

namespace rt::camera {

// Throws std::runtime_error (or the format's own error) naming the folder and what it lacks.
std::unique_ptr<sim::RecordedRgbdSource> open_recorded_site(const std::filesystem::path& dir);

// "RemoteTouch recording" or "k4a recordings", for messages.
std::string recorded_site_kind(const std::filesystem::path& dir);

}  // namespace rt::camera
