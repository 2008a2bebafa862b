#include "sim/leap_json.h"

#include <cmath>
#include <map>

#include "config/json.h"

namespace rt::sim {

using namespace config;  // the JSON readers

using config::JsonError;

namespace {

constexpr double kNominalFrameRate = 50.0;

// Leap's pointable ids: the hand's id times ten plus the digit type.
int64_t pointable_id(int32_t hand_id, int type) { return int64_t(hand_id) * 10 + type; }

Eigen::Vector3d require_unit(const nlohmann::json& object, const std::string& field, const std::string& where) {
  const Eigen::Vector3d v = require_vec3(object, field, where);
  if (std::abs(v.norm() - 1.0) > 1e-3) throw JsonError(where + ": field '" + field + "' must be a unit vector");
  return v;
}

TrackerHand hand_from_json(const nlohmann::json& json, const std::string& frame_where, size_t index) {
  std::string where = frame_where + " hands[" + std::to_string(index) + "]";
  if (!json.is_object()) throw JsonError(where + ": must be an object");
  TrackerHand hand;
  hand.id = int32_t(require_integer(json, "id", where, INT32_MIN, INT32_MAX));
  where = frame_where + " hand " + std::to_string(hand.id);
  const std::string type = config::require_string(json, "type", where);
  if (type != "left" && type != "right")
    throw JsonError(where + ": field 'type' must be \"left\" or \"right\", is \"" + type + "\"");
  hand.is_left = type == "left";
  hand.confidence = require_in_range(json, "confidence", where, 0.0, 1.0);
  hand.palm_position = require_vec3(json, "palmPosition", where);
  hand.palm_normal = require_unit(json, "palmNormal", where);
  hand.direction = require_unit(json, "direction", where);
  hand.wrist = require_vec3(json, "wrist", where);
  // Service versions differ (DESIGN.md section 6): the elbow and the arm's width may be absent,
  // and then there is no forearm to draw; present, they must be well-formed.
  hand.elbow.reset();
  if (json.contains("elbow") && !json["elbow"].is_null()) hand.elbow = require_vec3(json, "elbow", where);
  hand.palm_width = config::require_positive(json, "palmWidth", where);
  if (json.contains("armWidth") && !json["armWidth"].is_null())
    hand.arm_width = config::require_positive(json, "armWidth", where);
  return hand;
}

}  // namespace

nlohmann::json leap_json_from_frame(const TrackerFrame& frame) {
  nlohmann::json hands = nlohmann::json::array();
  nlohmann::json pointables = nlohmann::json::array();
  for (const TrackerHand& hand : frame.hands) {
    nlohmann::json entry = {{"id", hand.id},
                            {"type", hand.is_left ? "left" : "right"},
                            {"confidence", hand.confidence},
                            {"palmPosition", to_json(hand.palm_position)},
                            {"palmNormal", to_json(hand.palm_normal)},
                            {"direction", to_json(hand.direction)},
                            {"wrist", to_json(hand.wrist)},
                            {"palmWidth", hand.palm_width}};
    if (hand.elbow) entry["elbow"] = to_json(*hand.elbow);
    if (hand.arm_width) entry["armWidth"] = *hand.arm_width;
    hands.push_back(std::move(entry));
    for (int type = 0; type < kDigitCount; ++type) {
      const TrackerDigit& digit = hand.digits[type];
      pointables.push_back({{"id", pointable_id(hand.id, type)},
                            {"handId", hand.id},
                            {"type", type},
                            {"carpPosition", to_json(digit.carp)},
                            {"mcpPosition", to_json(digit.mcp)},
                            {"pipPosition", to_json(digit.pip)},
                            {"dipPosition", to_json(digit.dip)},
                            {"btipPosition", to_json(digit.btip)},
                            {"tipPosition", to_json(digit.tip)}});
    }
  }
  return {{"id", frame.id},
          {"timestamp", frame.timestamp_us},
          {"currentFrameRate", kNominalFrameRate},
          {"hands", hands},
          {"pointables", pointables}};
}

TrackerFrame frame_from_leap_json(const nlohmann::json& json) {
  if (!json.is_object()) throw JsonError("tracker frame: must be a JSON object, not " + std::string(json.type_name()));
  TrackerFrame frame;
  frame.id = require_integer(json, "id", "tracker frame");
  const std::string where = "frame " + std::to_string(frame.id);
  frame.timestamp_us = require_unsigned(json, "timestamp", where);

  const nlohmann::json& hands = config::require_array(json, "hands", where);
  std::map<int32_t, size_t> hand_index;
  for (size_t i = 0; i < hands.size(); ++i) {
    TrackerHand hand = hand_from_json(hands[i], where, i);
    if (!hand_index.emplace(hand.id, frame.hands.size()).second)
      throw JsonError(where + ": two hands have id " + std::to_string(hand.id));
    frame.hands.push_back(hand);
  }

  std::vector<std::array<bool, kDigitCount>> seen(frame.hands.size(), std::array<bool, kDigitCount>{});
  const nlohmann::json& pointables = config::require_array(json, "pointables", where);
  for (size_t i = 0; i < pointables.size(); ++i) {
    const std::string pointable_where = where + " pointables[" + std::to_string(i) + "]";
    const nlohmann::json& entry = pointables[i];
    if (!entry.is_object()) throw JsonError(pointable_where + ": must be an object");
    const auto hand_id = int32_t(require_integer(entry, "handId", pointable_where, INT32_MIN, INT32_MAX));
    const auto owner = hand_index.find(hand_id);
    if (owner == hand_index.end())
      throw JsonError(pointable_where + ": field 'handId' names hand " + std::to_string(hand_id) +
                      ", which is not in 'hands'");
    const int type = int(require_integer(entry, "type", pointable_where, 0, kDigitCount - 1));
    if (seen[owner->second][type])
      throw JsonError(pointable_where + ": hand " + std::to_string(hand_id) + " has two pointables of type " +
                      std::to_string(type));
    seen[owner->second][type] = true;
    TrackerDigit& digit = frame.hands[owner->second].digits[type];
    digit.carp = require_vec3(entry, "carpPosition", pointable_where);
    digit.mcp = require_vec3(entry, "mcpPosition", pointable_where);
    digit.pip = require_vec3(entry, "pipPosition", pointable_where);
    digit.dip = require_vec3(entry, "dipPosition", pointable_where);
    digit.btip = require_vec3(entry, "btipPosition", pointable_where);
    digit.tip = require_vec3(entry, "tipPosition", pointable_where);
  }
  for (size_t h = 0; h < frame.hands.size(); ++h)
    for (int type = 0; type < kDigitCount; ++type)
      if (!seen[h][type])
        throw JsonError(where + " hand " + std::to_string(frame.hands[h].id) + ": no pointable of type " +
                        std::to_string(type) + " (0 thumb .. 4 pinky) in 'pointables'");
  return frame;
}

std::string leap_json_line(const TrackerFrame& frame) { return leap_json_from_frame(frame).dump(); }

TrackerFrame parse_leap_json_line(std::string_view line) {
  nlohmann::json json;
  try {
    json = nlohmann::json::parse(line);
  } catch (const nlohmann::json::exception& error) {  // parse_error, or out_of_range for a number like 1E999
    throw JsonError(std::string("tracker frame is not valid JSON: ") + error.what());
  }
  return frame_from_leap_json(json);
}

}  // namespace rt::sim
