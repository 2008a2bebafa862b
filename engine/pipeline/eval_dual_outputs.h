#pragma once
// What `eval dual` writes besides metrics.json: frames.csv (a row per frame, variant and user),
// the crops of the contact sheets (the paper's results figure: image-only far, dual in the
// approach, dual at the glass, image-only at the glass, dual without appearance adaption at the
// glass, each beside the truth), the goals the issue set, the closing table, and the plots,
// drawn by scripts/plot_eval_dual.py with matplotlib.
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "evaluation/region_scores.h"
#include "evaluation/touch_phase.h"
#include "image/host_image.h"
#include "image/image_crop.h"

namespace rt::pipeline {

struct FrameRecord {
  std::string user;
  uint32_t scene_frame = 0;
  double time_s = 0;
  double distance_m = 0;          // of the true hand: the phase
  double tracked_distance_m = 0;  // of the tracked hand: what Eq. 4 is given (NaN: no hand)
  std::optional<evaluation::TouchPhase> phase;
  std::optional<uint64_t> skeleton_gap_us;  // portrait capture to the skeleton samples used
  size_t hand_arm_pixels = 0;
};

class DualEvalOutputs {
 public:
  explicit DualEvalOutputs(const std::filesystem::path& dir);
  // One variant's result for a frame; `shown` rgba32f straight alpha, `truth` rgba8 premultiplied.
  void add_frame(const FrameRecord& record, const std::string& variant, const evaluation::FrameScore& score,
                 std::optional<double> tip_error_px, const HostImage& shown, const HostImage& truth,
                 const evaluation::HandRegion& region);
  // Writes the sheets' crops and sheet/sheet.json.
  void finish();

 private:
  struct Chosen {
    double rank = 0;  // lower is better
    FrameRecord record;
    std::optional<double> psnr_db;
    HostImage shown, truth;  // rgba8, cut to the hand and forearm
  };

  std::filesystem::path dir_;
  std::ofstream csv_;
  std::map<std::pair<std::string, std::string>, Chosen> chosen_;  // (user, slot)
};

// The goals, each with the figures it compares and whether it is met (where the
// scene has the phases and the run the variants it needs).
nlohmann::json check_goals(const nlohmann::json& report);
void print_summary(const nlohmann::json& report);
// Runs scripts/plot_eval_dual.py on `dir`: hand_psnr.png and sheet_<user>.png. Throws
// std::runtime_error saying what to install when it cannot.
void plot_eval_dual(const std::filesystem::path& dir);

}  // namespace rt::pipeline
