#pragma once
// What a site records beside its ground truth so that the frames the other site displayed can be
// measured where it matters: truth/frame_NNNN.png (the truth over the background, written by the
// sender), truth/hand_NNNN.png (the region of the hand and forearm reaching for the glass,
// evaluation/hand_region.h) and a line of truth/hands.jsonl per frame (the hand's distance to the
// screen and its touch phase). The demo measures each site's displayed frames against the other
// site's record.
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "evaluation/hand_region.h"
#include "evaluation/touch_phase.h"

namespace rt::site {

class TruthRegionWriter {
 public:
  explicit TruthRegionWriter(const std::filesystem::path& truth_dir);
  void write(uint64_t frame, const evaluation::HandRegion& region, double distance_m,
             std::optional<evaluation::TouchPhase> phase);

 private:
  std::filesystem::path dir_;
  std::ofstream lines_;
};

// Site `shown`'s displayed frames (frames.jsonl, frames/) against site `captured`'s record of the
// same captured frames: the whole frame's PSNR (final and mean) and, per touch phase, the hand
// and forearm's PSNR and the hand's CIEDE2000 (both over the background the display shows).
// Missing or unreadable files leave frames out; the counts say how many were measured.
nlohmann::json measure_displayed_frames(const std::filesystem::path& shown, const std::filesystem::path& captured);

}  // namespace rt::site
