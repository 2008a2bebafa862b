#include "pipeline/accuracy_outputs.h"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <stdexcept>

#include "pipeline/plot_script.h"

namespace rt::pipeline {

namespace {

std::string figure(const char* format, double value) {
  char text[32];
  std::snprintf(text, sizeof text, format, value);
  return text;
}

}  // namespace

void write_pareto_md(const std::filesystem::path& path, const std::vector<AccuracyRow>& rows, const AccuracyRunInfo& info) {
  std::vector<const AccuracyRow*> front;
  for (const AccuracyRow& row : rows)
    if (row.on_front) front.push_back(&row);
  std::sort(front.begin(), front.end(), [](const AccuracyRow* a, const AccuracyRow* b) { return a->gpu_ms < b->gpu_ms; });
  std::ofstream out(path);
  if (!out) throw std::runtime_error("cannot write " + path.string());
  out << "Command: `" << info.command << "`\n\n"
      << "On " << info.device << "; " << info.frames << "; portraits " << info.width << "x" << info.height
      << " unless the options say otherwise. " << rows.size() << " configurations measured, " << front.size()
      << " on the front: no other is as accurate (psnr_fg_db) and as fast, and better in one. GPU ms: a frame's "
         "passes summed (timestamp queries), the median over the frames, the quartiles in brackets. hand front: also "
         "on the front of psnr_hand_db against GPU ms.\n\n"
      << "| options | psnr_fg_db | psnr_hand_db | depth_mae_edge_mm | alpha_iou | GPU ms/frame | hand front |\n"
      << "|---|---|---|---|---|---|---|\n";
  for (const AccuracyRow* row : front)
    out << "| " << (row->options.empty() ? "the defaults" : "`" + row->options + "`") << " | "
        << figure("%.2f", row->psnr_fg_db) << " | " << figure("%.2f", row->psnr_hand_db) << " | "
        << figure("%.2f", row->depth_mae_edge_mm) << " | " << figure("%.4f", row->alpha_iou) << " | "
        << figure("%.1f", row->gpu_ms) << " (" << figure("%.1f", row->gpu_ms_q1) << "-" << figure("%.1f", row->gpu_ms_q3)
        << ") | " << (row->on_front_hand ? "yes" : "no") << " |\n";
}

void plot_accuracy(const std::filesystem::path& dir) {
  run_plot_script("plot_accuracy.py", dir, "bench accuracy", "results.csv and pareto.md are written; --no-plot skips the plot");
}

}  // namespace rt::pipeline
