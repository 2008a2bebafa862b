#pragma once
// Reading and writing the JSON documents of the engine (site descriptions, calibration, scenes,
// tracker frames, site configs) with errors that name the field and say what is wrong, e.g.
// "camera 'top-left': field 'fx' must be a number > 0". One module: files, fields, numbers in a
// range, integers, vectors, colors, unknown fields.
#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include <cstdint>
#include <filesystem>
#include <initializer_list>
#include <stdexcept>
#include <string>

namespace rt::config {

class JsonError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Parses a file; the error names the file and the line/column where parsing failed.
nlohmann::json read_json_file(const std::filesystem::path& path);
void write_json_file(const std::filesystem::path& path, const nlohmann::json& document);

// `where` prefixes every error, e.g. "camera 'top-left'".
const nlohmann::json& require(const nlohmann::json& object, const std::string& field, const std::string& where);
double require_number(const nlohmann::json& object, const std::string& field, const std::string& where);
double require_positive(const nlohmann::json& object, const std::string& field, const std::string& where);
std::string require_string(const nlohmann::json& object, const std::string& field, const std::string& where);
const nlohmann::json& require_array(const nlohmann::json& object, const std::string& field, const std::string& where,
                                    size_t min_size = 0, size_t max_size = size_t(-1));

// Vectors, colors, ranges and integers.
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

}  // namespace rt::config
