#include "site/site_metrics.h"

#include <algorithm>

#include "pipeline/hand_settings.h"
#include "pipeline/ibr_settings.h"

namespace rt::site {

nlohmann::json timings_json(const vk::FrameGraph& graph) {
  nlohmann::json out = nlohmann::json::object();
  double total = 0;
  for (const auto& timing : graph.timings()) {
    out[timing.name] = timing.median_ms;
    total += timing.median_ms;
  }
  out["total"] = total;
  return out;
}

void SiteCommon::record_gpu_ms(const std::string& stage, const vk::FrameGraph& graph) {
  nlohmann::json timings = timings_json(graph);
  std::lock_guard lock(gpu_ms_mutex_);
  gpu_ms_[stage] = std::move(timings);
}

nlohmann::json SiteCommon::gpu_ms() const {
  std::lock_guard lock(gpu_ms_mutex_);
  return gpu_ms_;
}

nlohmann::json site_metrics(const SiteCommon& common, double elapsed_s) {
  const net::NetCounters counters = common.net->counters();
  nlohmann::json m;
  m["site"] = common.name;
  m["scene"] = common.scene.name;
  m["device"] = common.context->device_name();
  m["width"] = common.width;
  m["height"] = common.height;
  m["scene_frames"] = common.scene.frame_count;
  m["resolution_scale"] = common.scene.resolution_scale;
  m["time_scale"] = common.options.time_scale;
  m["elapsed_s"] = elapsed_s;
  m["ibr"] = pipeline::ibr_settings_json(common.options.ibr);
  m["quality"] = common.options.quality;
  m["hand"] = pipeline::hand_settings_json(common.options.hand);
  m["gpu_ms"] = common.gpu_ms();
  m["latency_notes"] =
      "portrait and hand: the remote sender's capture time to this site's display (both processes share the "
      "monotonic clock on one machine); touch: the later of the two skeletons that showed the touch to the motor command";
  const double wall = std::max(elapsed_s, 1e-6);
  m["bytes_per_s"] = {{"out", double(counters.bytes_out) / wall}, {"in", double(counters.bytes_in) / wall}};
  m["net"] = counters.to_json();
  m["transport"] = common.net->transport_json();
  m["touch"] = {{"starts", common.events->count("touch_start")},
                {"ends", common.events->count("touch_end")},
                {"motor_pulses", common.events->count("motor_pulse")}};
  return m;
}

}  // namespace rt::site
