#include "pipeline/ibr_evaluation.h"

#include <algorithm>
#include <cmath>

namespace rt::pipeline {

namespace {

bool all_finite(const HostImage& image) {
  return std::all_of(image.texels.begin(), image.texels.end(), [](float v) { return std::isfinite(v); });
}

// Linear interpolation between order statistics, as numpy's default.
double quantile(std::vector<double> values, double q) {
  if (values.empty()) return std::nan("");
  std::sort(values.begin(), values.end());
  const double position = q * double(values.size() - 1);
  const size_t below = size_t(std::floor(position));
  const size_t above = std::min(below + 1, values.size() - 1);
  return values[below] + (position - double(below)) * (values[above] - values[below]);
}

}  // namespace

FrameMeasurement IbrEvaluation::measure_frame(GpuSession& session, IbrRenderer& renderer, uint32_t frame_index,
                                              const std::vector<sim::RgbdImage>& cameras,
                                              const std::vector<size_t>& selection, const Camera& target,
                                              const PortraitTruth& truth) {
  renderer.prepare(cameras, selection, target);
  session.run_frame(renderer.graph(), frame_index);
  FrameMeasurement frame;
  vk::Context& context = session.context();
  frame.portrait = vk::download(context, renderer.portrait());
  frame.depth = vk::download(context, renderer.portrait_depth());
  frame.error = metrics_.add(frame.portrait, frame.depth, truth.color, truth.depth_m, truth.part);
  for (const auto& timing : renderer.graph().timings()) frame.gpu_ms += timing.last_ms;
  frame_psnr_fg_db_.push_back(frame.error.psnr_fg_db);
  frame_gpu_ms_.push_back(frame.gpu_ms);
  if (!non_finite_output_) {
    const std::string which = " of frame " + std::to_string(frames_);
    if (!all_finite(frame.portrait)) non_finite_output_ = "portrait" + which;
    else if (!all_finite(frame.depth)) non_finite_output_ = "portrait depth" + which;
    else if (!std::isfinite(frame.gpu_ms)) non_finite_output_ = "GPU ms" + which;
  }
  ++frames_;
  return frame;
}

double IbrEvaluation::gpu_ms_quantile(double q) const { return quantile(frame_gpu_ms_, q); }

std::optional<std::string> IbrEvaluation::non_finite() const {
  if (non_finite_output_) return non_finite_output_;
  const std::pair<const char*, double> figures[] = {{"psnr_fg_db", metrics_.psnr_fg_db()},
                                                    {"psnr_hand_db", metrics_.psnr_hand_db()},
                                                    {"depth_mae_edge_mm", metrics_.depth_mae_edge_mm()},
                                                    {"alpha_iou", metrics_.alpha_iou()}};
  for (const auto& [name, value] : figures)
    if (!std::isfinite(value)) return std::string(name);
  return std::nullopt;
}

nlohmann::json IbrEvaluation::to_json(const vk::FrameGraph& graph) const {
  nlohmann::json result = metrics_.to_json();
  double total_ms = 0;
  for (const auto& timing : graph.timings()) {
    result["gpu_ms"][timing.name] = timing.median_ms;
    total_ms += timing.median_ms;
  }
  result["gpu_ms_total"] = total_ms;
  result["gpu_ms_frame_median"] = gpu_ms_quantile(0.5);
  result["gpu_ms_frame_q1"] = gpu_ms_quantile(0.25);
  result["gpu_ms_frame_q3"] = gpu_ms_quantile(0.75);
  result["frame_psnr_fg_db"] = frame_psnr_fg_db_;
  return result;
}

}  // namespace rt::pipeline
