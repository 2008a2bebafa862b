#pragma once
// Leap Motion WebSocket protocol v6 frames (DESIGN.md section 6), one frame per line in
// tracker.jsonl. The writer emits the fields the project uses; the parser reads frames from the
// simulator and from a real device (extra fields such as "bases" or "r" are ignored) and rejects
// a malformed frame with an error that names the field.
#include <nlohmann/json.hpp>

#include <string>
#include <string_view>

#include "sim/tracker_frame.h"

namespace rt::sim {

// {"id", "timestamp", "currentFrameRate", "hands": [{"id", "type": "left"|"right", "confidence",
// "palmPosition", "palmNormal", "direction", "wrist", "elbow" (optional), "palmWidth", "armWidth"
// (optional)}], "pointables":
// [{"id", "handId", "type": 0..4, "carpPosition", "mcpPosition", "pipPosition", "dipPosition",
// "btipPosition", "tipPosition"}]}. Every double is written so that it reads back exactly.
nlohmann::json leap_json_from_frame(const TrackerFrame& frame);
// Throws config::JsonError, e.g. "frame 41 hand 3: field 'palmPosition' must hold 3 numbers".
TrackerFrame frame_from_leap_json(const nlohmann::json& json);

std::string leap_json_line(const TrackerFrame& frame);  // no newline
TrackerFrame parse_leap_json_line(std::string_view line);

}  // namespace rt::sim
