#pragma once
// One configuration of the image-based model measured against the simulator's ground truth,
// frame by frame: what `eval ibr` and `bench accuracy` both report. It renders with a renderer
// the caller owns (a measurement may span renderers, e.g. one per scene), downloads the portrait,
// accumulates the portrait metrics (ibr/portrait_metrics.h) and each frame's GPU ms summed over
// the passes, and notes the first output that is not finite.
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "geometry/camera.h"
#include "ibr/portrait_metrics.h"
#include "image/host_image.h"
#include "pipeline/gpu_session.h"
#include "pipeline/ibr_renderer.h"
#include "sim/rgbd_source.h"

namespace rt::pipeline {

// The simulator's render of the target view (see RgbdRenderer::target_color and friends).
struct PortraitTruth {
  HostImage color;    // rgba8 premultiplied by coverage
  HostImage depth_m;  // r32f
  HostImage part;     // r32f RT_PART_*
};

struct FrameMeasurement {
  HostImage portrait;  // rgba32f straight alpha
  HostImage depth;     // r32f metres
  ibr::PortraitError error;
  double gpu_ms = 0;   // summed over the graph's passes
};

class IbrEvaluation {
 public:
  // Renders one frame of `renderer` (`frame_index` for a RenderDoc capture) and measures it.
  FrameMeasurement measure_frame(GpuSession& session, IbrRenderer& renderer, uint32_t frame_index,
                                 const std::vector<sim::RgbdImage>& cameras, const std::vector<size_t>& selection,
                                 const Camera& target, const PortraitTruth& truth);

  const ibr::PortraitMetrics& metrics() const { return metrics_; }
  const std::vector<double>& frame_psnr_fg_db() const { return frame_psnr_fg_db_; }
  const std::vector<double>& frame_gpu_ms() const { return frame_gpu_ms_; }
  // Of the per-frame GPU totals: q = 0.5 is the median, 0.25 and 0.75 the spread's quartiles.
  double gpu_ms_quantile(double q) const;
  // The first output or figure that is NaN or infinite ("portrait of frame 3", "psnr_fg_db"),
  // none when all are finite. A configuration with one is a failed measurement.
  std::optional<std::string> non_finite() const;

  // The metrics, `gpu_ms` per pass (medians of `graph`), `gpu_ms_total` (their sum),
  // `gpu_ms_frame_median` / `_q1` / `_q3` and `frame_psnr_fg_db`.
  nlohmann::json to_json(const vk::FrameGraph& graph) const;

 private:
  ibr::PortraitMetrics metrics_;
  std::vector<double> frame_psnr_fg_db_;
  std::vector<double> frame_gpu_ms_;
  std::optional<std::string> non_finite_output_;
  size_t frames_ = 0;
};

}  // namespace rt::pipeline
