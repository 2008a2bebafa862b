#pragma once
// Readers for the vectors, colors and integers of the simulator's JSON files (site descriptions,
// scenes, tracker frames), on top of config/json_fields.h: every error names the field.
#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include <cstdint>
#include <initializer_list>
#include <string>

namespace rt::sim {

Eigen::Vector2d require_vec2(const nlohmann::json& object, const std::string& field, const std::string& where);
Eigen::Vector3d require_vec3(const nlohmann::json& object, const std::string& field, const std::string& where);
// Three numbers in [0, 1].
Eigen::Vector3f require_rgb(const nlohmann::json& object, const std::string& field, const std::string& where);
// A number within [low, high].
double require_in_range(const nlohmann::json& object, const std::string& field, const std::string& where, double low,
                        double high);
int64_t require_integer(const nlohmann::json& object, const std::string& field, const std::string& where,
                        int64_t low = INT64_MIN, int64_t high = INT64_MAX);
uint64_t require_unsigned(const nlohmann::json& object, const std::string& field, const std::string& where);
const nlohmann::json& require_object(const nlohmann::json& object, const std::string& field, const std::string& where);

// Scene and site files are written by hand: a misspelt optional field would otherwise be ignored
// silently, so any field not in `known` is an error that lists the known ones.
void reject_unknown_fields(const nlohmann::json& object, std::initializer_list<const char*> known,
                           const std::string& where);

// Shortest text that reads back as the same number: "1", "0.25", not "1.000000".
std::string format_number(double value);

nlohmann::json to_json(const Eigen::Vector2d& v);
nlohmann::json to_json(const Eigen::Vector3d& v);
nlohmann::json to_json(const Eigen::Vector3f& v);

}  // namespace rt::sim
