#pragma once
// The site's metrics.json: what the run knows (scene, device, clock, link, touches); the sender
// and the receiver add their own counters (Sender::add_metrics, Receiver::add_metrics).
#include <nlohmann/json.hpp>

#include "site/site_common.h"
#include "vulkan/frame_graph.h"

namespace rt::site {

nlohmann::json site_metrics(const SiteCommon& common, double elapsed_s);

// Median GPU ms of each pass of `graph` and their total.
nlohmann::json timings_json(const vk::FrameGraph& graph);

}  // namespace rt::site
