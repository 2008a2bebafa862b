#pragma once
// What `bench accuracy` leaves besides results.csv: pareto.md (the front as a table, with the
// command that made it) and pareto.png (drawn by scripts/plot_accuracy.py with matplotlib).
#include <filesystem>
#include <string>
#include <vector>

#include "pipeline/accuracy_results.h"

namespace rt::pipeline {

struct AccuracyRunInfo {
  std::string command;  // the command line that reproduces the run
  std::string device;
  std::string frames;   // which frames of which scenes, in words
  uint32_t width = 0, height = 0;  // the base portrait size
};

// `rows` with their fronts marked (mark_fronts).
void write_pareto_md(const std::filesystem::path& path, const std::vector<AccuracyRow>& rows, const AccuracyRunInfo& info);
// Runs scripts/plot_accuracy.py on `dir`; throws saying what failed and what it needs.
void plot_accuracy(const std::filesystem::path& dir);

}  // namespace rt::pipeline
