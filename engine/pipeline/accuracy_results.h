#pragma once
// `bench accuracy`'s results.csv: one row per configuration, its settings as columns (each
// knob of ibr_knobs() by its JSON key, the cameras' resolution scale, the portrait size) and
// what was measured; the Pareto fronts of accuracy against GPU time; and the choice of the most
// accurate configuration within a time budget (--budget-ms). CPU only.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "pipeline/ibr_settings.h"

namespace rt::pipeline {

struct AccuracyRow {
  std::string options;  // the configuration's command-line words (accuracy_grid.h); its name
  IbrSettings ibr;      // every knob; width and height are the portrait's
  double resolution_scale = 0;  // the cameras' scale actually used
  std::string scenes;           // "wave+clap+approach"
  uint32_t frames = 0;          // measured, over all scenes
  double psnr_fg_db = 0, psnr_hand_db = 0, depth_mae_edge_mm = 0, alpha_iou = 0;
  double gpu_ms = 0, gpu_ms_q1 = 0, gpu_ms_q3 = 0;  // per frame, summed over passes: median, quartiles
  double wall_s = 0;                                // the measurement's wall time (not the simulation's)
  bool on_front = false;       // no other row is as accurate (psnr_fg_db) and as fast, and better in one
  bool on_front_hand = false;  // the same with psnr_hand_db
};

std::vector<std::string> accuracy_csv_columns();

// Writes every row (to a temporary file first, so a stopped run never leaves half a file).
void write_accuracy_csv(const std::filesystem::path& path, const std::vector<AccuracyRow>& rows);
// Throws std::runtime_error naming the file, the line and the column for anything it cannot
// read, and for a header other than accuracy_csv_columns().
std::vector<AccuracyRow> read_accuracy_csv(const std::filesystem::path& path);

// Sets on_front and on_front_hand of every row.
void mark_fronts(std::vector<AccuracyRow>& rows);

// The row with the best psnr_fg_db among those of this portrait size whose gpu_ms is at most
// `budget_ms`. Throws std::runtime_error saying why none fits: no row of that size (naming the
// sizes there are), or the fastest of them and its time.
const AccuracyRow& most_accurate_within(const std::vector<AccuracyRow>& rows, double budget_ms, uint32_t width,
                                        uint32_t height, const std::string& where);

}  // namespace rt::pipeline
