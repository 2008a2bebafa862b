#include "sim/leap_json.h"

#include <Eigen/Geometry>

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

bool present(const nlohmann::json& object, const char* field) { return object.contains(field) && !object[field].is_null(); }

std::optional<Eigen::Vector3d> optional_vec3(const nlohmann::json& object, const char* field, const std::string& where) {
  if (!present(object, field)) return std::nullopt;
  return require_vec3(object, field, where);
}

std::optional<Eigen::Vector3d> optional_unit(const nlohmann::json& object, const char* field, const std::string& where) {
  if (!present(object, field)) return std::nullopt;
  return require_unit(object, field, where);
}

// What a hand entry gives: the fields a service may leave out are empty until
// derive_missing_fields fills them from the digits.
struct HandEntry {
  TrackerHand hand;
  std::optional<Eigen::Vector3d> palm_position, palm_normal, direction, wrist;
};

HandEntry hand_from_json(const nlohmann::json& json, const std::string& frame_where, size_t index) {
  std::string where = frame_where + " hands[" + std::to_string(index) + "]";
  if (!json.is_object()) throw JsonError(where + ": must be an object");
  HandEntry entry;
  TrackerHand& hand = entry.hand;
  hand.id = int32_t(require_integer(json, "id", where, INT32_MIN, INT32_MAX));
  where = frame_where + " hand " + std::to_string(hand.id);
  const std::string type = config::require_string(json, "type", where);
  if (type != "left" && type != "right")
    throw JsonError(where + ": field 'type' must be \"left\" or \"right\", is \"" + type + "\"");
  hand.is_left = type == "left";
  // A service that does not grade its hands tracks them as well as it can: full confidence.
  hand.confidence = present(json, "confidence") ? require_in_range(json, "confidence", where, 0.0, 1.0) : 1.0;
  entry.palm_position = optional_vec3(json, "palmPosition", where);
  entry.palm_normal = optional_unit(json, "palmNormal", where);
  entry.direction = optional_unit(json, "direction", where);
  entry.wrist = optional_vec3(json, "wrist", where);
  // Service versions differ (DESIGN.md section 6): the elbow and the arm's width may be absent,
  // and then there is no forearm to draw; the palm's width too, and then only bone lengths are
  // fitted. Present, they must be well-formed.
  hand.elbow = optional_vec3(json, "elbow", where);
  hand.palm_width.reset();
  if (present(json, "palmWidth")) hand.palm_width = config::require_positive(json, "palmWidth", where);
  if (present(json, "armWidth")) hand.arm_width = config::require_positive(json, "armWidth", where);
  return entry;
}

// The digit's joints; either tip may stand for the other (in Leap's model they are the same point
// but for the nail's padding), and a missing carp of the thumb is its mcp (Leap's thumb
// metacarpal has zero length). A finger's missing carp is left for derive_missing_fields.
bool digit_from_json(const nlohmann::json& entry, int type, TrackerDigit& digit, const std::string& where) {
  digit.mcp = require_vec3(entry, "mcpPosition", where);
  digit.pip = require_vec3(entry, "pipPosition", where);
  digit.dip = require_vec3(entry, "dipPosition", where);
  const std::optional<Eigen::Vector3d> btip = optional_vec3(entry, "btipPosition", where);
  const std::optional<Eigen::Vector3d> tip = optional_vec3(entry, "tipPosition", where);
  if (!btip && !tip) throw JsonError(where + ": neither 'tipPosition' nor 'btipPosition': the digit has no end");
  digit.tip = tip ? *tip : *btip;
  digit.btip = btip ? *btip : *tip;
  const std::optional<Eigen::Vector3d> carp = optional_vec3(entry, "carpPosition", where);
  if (carp) digit.carp = *carp;
  else if (type == int(Digit::Thumb)) digit.carp = digit.mcp;
  return carp.has_value() || type == int(Digit::Thumb);
}

// Fills what the service left out from what it sent, in Leap's own geometry:
//   wrist      the mean of the four fingers' carps (where Leap's metacarpals begin, at the carpal
//              bones, about a centimetre from its wrist point)
//   a carp     of a finger, the wrist
//   direction  from the wrist to the middle finger's mcp
//   palm       halfway between the wrist and the mean of the fingers' mcps
//   normal     across the knuckles (index to pinky) crossed with the direction, out of the palm
//              (the order of the cross product follows the hand's side)
// A hand with neither its wrist nor every finger's carp cannot be placed: refused, naming them.
void derive_missing_fields(HandEntry& entry, const std::array<bool, kDigitCount>& carp_given, const std::string& where) {
  TrackerHand& hand = entry.hand;
  const int fingers[] = {int(Digit::Index), int(Digit::Middle), int(Digit::Ring), int(Digit::Pinky)};
  if (!entry.wrist) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (int d : fingers) {
      if (!carp_given[size_t(d)])
        throw JsonError(where + ": no 'wrist' and no 'carpPosition' for digit " + std::to_string(d) +
                        ": the hand cannot be placed");
      sum += hand.digits[size_t(d)].carp;
    }
    entry.wrist = sum / 4.0;
  }
  hand.wrist = *entry.wrist;
  for (int d : fingers)
    if (!carp_given[size_t(d)]) hand.digits[size_t(d)].carp = hand.wrist;
  Eigen::Vector3d mean_mcp = Eigen::Vector3d::Zero();
  for (int d : fingers) mean_mcp += hand.digits[size_t(d)].mcp / 4.0;
  if (!entry.direction) {
    const Eigen::Vector3d along = hand.digits[size_t(Digit::Middle)].mcp - hand.wrist;
    if (!(along.norm() > 1e-6)) throw JsonError(where + ": no 'direction', and the middle finger's mcp is at the wrist");
    entry.direction = along.normalized();
  }
  hand.direction = *entry.direction;
  hand.palm_position = entry.palm_position ? *entry.palm_position : Eigen::Vector3d(0.5 * (hand.wrist + mean_mcp));
  if (!entry.palm_normal) {
    const Eigen::Vector3d across = hand.digits[size_t(Digit::Index)].mcp - hand.digits[size_t(Digit::Pinky)].mcp;
    const Eigen::Vector3d normal = hand.is_left ? hand.direction.cross(across) : across.cross(hand.direction);
    if (!(normal.norm() > 1e-6))
      throw JsonError(where + ": no 'palmNormal', and the knuckles lie along the hand's direction");
    entry.palm_normal = normal.normalized();
  }
  hand.palm_normal = *entry.palm_normal;
  // Huge but finite coordinates can overflow what is derived from them (a mean, a difference).
  const std::pair<const char*, const Eigen::Vector3d*> derived[] = {
      {"wrist", &hand.wrist}, {"direction", &hand.direction}, {"palmPosition", &hand.palm_position}, {"palmNormal", &hand.palm_normal}};
  for (const auto& [name, value] : derived)
    if (!value->allFinite())
      throw JsonError(where + ": '" + name + "' comes out infinite or NaN from the coordinates given (too large)");
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
                            {"wrist", to_json(hand.wrist)}};
    if (hand.palm_width) entry["palmWidth"] = *hand.palm_width;
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
  std::vector<HandEntry> entries;
  for (size_t i = 0; i < hands.size(); ++i) {
    HandEntry entry = hand_from_json(hands[i], where, i);
    if (!hand_index.emplace(entry.hand.id, entries.size()).second)
      throw JsonError(where + ": two hands have id " + std::to_string(entry.hand.id));
    entries.push_back(std::move(entry));
  }

  std::vector<std::array<bool, kDigitCount>> seen(entries.size(), std::array<bool, kDigitCount>{});
  std::vector<std::array<bool, kDigitCount>> carp_given(entries.size(), std::array<bool, kDigitCount>{});
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
    carp_given[owner->second][size_t(type)] =
        digit_from_json(entry, type, entries[owner->second].hand.digits[size_t(type)], pointable_where);
  }
  for (size_t h = 0; h < entries.size(); ++h) {
    const std::string hand_where = where + " hand " + std::to_string(entries[h].hand.id);
    for (int type = 0; type < kDigitCount; ++type)
      if (!seen[h][type])
        throw JsonError(hand_where + ": no pointable of type " + std::to_string(type) + " (0 thumb .. 4 pinky) in 'pointables'");
    derive_missing_fields(entries[h], carp_given[h], hand_where);
    frame.hands.push_back(entries[h].hand);
  }
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
