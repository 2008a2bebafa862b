#pragma once
// `remotetouch record`: a site's live k4a cameras written as k4a recordings, one
// `<camera name>.mkv` per camera beside the site's `site.json`, the folder a site of recordings
// plays (k4a_site_recordings.h). Colour is stored as the device gave it (no second JPEG
// encoding); depth, the calibration, the modes and the wired-sync role as the SDK's recorder
// stores them.
#include <cstdio>
#include <filesystem>
#include <memory>
#include <vector>

#include "camera/k4a_library.h"
#include "sim/site_description.h"

namespace rt::camera::k4a {

struct RecordSummary {
  std::vector<size_t> captures;  // written, per camera
  size_t skipped = 0;            // bad captures, and ones whose time did not increase
  double seconds = 0;            // wall time recorded
  // This machine's monotonic clock minus the frame sets' clock (the first camera's device time,
  // a subordinate's delay taken off), from the capture that arrived soonest after it was taken:
  // how another device's frames, stamped when they arrive, are put on the recording's clock.
  int64_t host_minus_device_us = 0;
};

// Records every camera of `site` (all live: source "k4a") for `seconds` of wall time, or until
// every device has stopped giving captures. `out` must not hold a site already. Throws
// LiveError, or config::JsonError for a site file whose cameras are not all live. `log` (may
// be null) gets the problems, a few lines.
RecordSummary record_live_site(const sim::SiteDescription& site, const std::string& site_where,
                               const std::filesystem::path& out, double seconds, std::FILE* log = stderr,
                               std::shared_ptr<const Library> library = nullptr);

}  // namespace rt::camera::k4a
