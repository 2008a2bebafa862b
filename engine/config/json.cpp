#include "config/json.h"

#include <cerrno>
#include <charconv>
#include <cstring>
#include <cmath>
#include <fstream>

namespace rt::config {


namespace {
constexpr uintmax_t kMaxJsonFileBytes = uintmax_t(64) << 20;
}  // namespace

nlohmann::json read_json_file(const std::filesystem::path& path) {
  std::ifstream file(path);
  if (!file) throw JsonError("cannot open '" + path.string() + "': " + std::strerror(errno));
  // Parsing keeps the whole document in memory: a file far larger than any of ours (a device,
  // a mistaken path) is refused before it is read.
  std::error_code size_error;
  const uintmax_t size = std::filesystem::file_size(path, size_error);
  if (size_error || size > kMaxJsonFileBytes)
    throw JsonError("'" + path.string() + "' is " + (size_error ? "not a regular file" : std::to_string(size) + " bytes") +
                    ": a JSON file of ours is at most " + std::to_string(kMaxJsonFileBytes >> 20) + " MiB");
  try {
    return nlohmann::json::parse(file);
  } catch (const nlohmann::json::exception& error) {  // parse errors, and numbers out of range (1E999)
    throw JsonError("'" + path.string() + "' is not valid JSON: " + error.what());
  }
}

void write_json_file(const std::filesystem::path& path, const nlohmann::json& document) {
  if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path());
  std::ofstream file(path);
  if (!file) throw JsonError("cannot write '" + path.string() + "'");
  file << document.dump(2) << "\n";
  if (!file) throw JsonError("writing '" + path.string() + "' failed");
}

const nlohmann::json& require(const nlohmann::json& object, const std::string& field, const std::string& where) {
  if (!object.is_object()) throw JsonError(where + ": expected an object");
  const auto it = object.find(field);
  if (it == object.end()) throw JsonError(where + ": missing field '" + field + "'");
  return *it;
}

double require_number(const nlohmann::json& object, const std::string& field, const std::string& where) {
  const nlohmann::json& value = require(object, field, where);
  if (!value.is_number()) throw JsonError(where + ": field '" + field + "' must be a number, not " + value.type_name());
  const double number = value.get<double>();
  if (!std::isfinite(number)) throw JsonError(where + ": field '" + field + "' must be finite");
  return number;
}

double require_positive(const nlohmann::json& object, const std::string& field, const std::string& where) {
  const double number = require_number(object, field, where);
  if (!(number > 0.0)) throw JsonError(where + ": field '" + field + "' must be > 0, is " + std::to_string(number));
  return number;
}

std::string require_string(const nlohmann::json& object, const std::string& field, const std::string& where) {
  const nlohmann::json& value = require(object, field, where);
  if (!value.is_string()) throw JsonError(where + ": field '" + field + "' must be a string, not " + value.type_name());
  return value.get<std::string>();
}

const nlohmann::json& require_array(const nlohmann::json& object, const std::string& field, const std::string& where,
                                    size_t min_size, size_t max_size) {
  const nlohmann::json& value = require(object, field, where);
  if (!value.is_array()) throw JsonError(where + ": field '" + field + "' must be an array, not " + value.type_name());
  if (value.size() < min_size || value.size() > max_size)
    throw JsonError(where + ": field '" + field + "' has " + std::to_string(value.size()) + " entries, expected " +
                    (min_size == max_size ? std::to_string(min_size)
                                          : std::to_string(min_size) + " to " +
                                                (max_size == size_t(-1) ? "any" : std::to_string(max_size))));
  for (const auto& entry : value)
    if (entry.is_number() && !std::isfinite(entry.get<double>()))
      throw JsonError(where + ": field '" + field + "' holds a non-finite number");
  return value;
}



namespace {

template <int N>
Eigen::Matrix<double, N, 1> require_vector(const nlohmann::json& object, const std::string& field,
                                           const std::string& where) {
  const nlohmann::json& array = require_array(object, field, where, N, N);
  Eigen::Matrix<double, N, 1> v;
  for (int i = 0; i < N; ++i) {
    if (!array[i].is_number())
      throw JsonError(where + ": field '" + field + "' must hold " + std::to_string(N) + " numbers; entry " +
                      std::to_string(i) + " is " + array[i].type_name());
    v[i] = array[i].get<double>();
  }
  return v;
}

}  // namespace

std::string format_number(double value) {
  char text[64];
  const auto result = std::to_chars(text, text + sizeof text, value);
  return std::string(text, result.ptr);
}

Eigen::Vector2d require_vec2(const nlohmann::json& object, const std::string& field, const std::string& where) {
  return require_vector<2>(object, field, where);
}

Eigen::Vector3d require_vec3(const nlohmann::json& object, const std::string& field, const std::string& where) {
  return require_vector<3>(object, field, where);
}

Eigen::Vector3f require_rgb(const nlohmann::json& object, const std::string& field, const std::string& where) {
  const Eigen::Vector3d rgb = require_vector<3>(object, field, where);
  if ((rgb.array() < 0.0).any() || (rgb.array() > 1.0).any())
    throw JsonError(where + ": field '" + field + "' must hold three numbers in [0, 1] (linear RGB)");
  return rgb.cast<float>();
}

double require_in_range(const nlohmann::json& object, const std::string& field, const std::string& where, double low,
                        double high) {
  const double value = require_number(object, field, where);
  if (value < low || value > high)
    throw JsonError(where + ": field '" + field + "' must be in [" + format_number(low) + ", " + format_number(high) +
                    "], is " + format_number(value));
  return value;
}

int64_t require_integer(const nlohmann::json& object, const std::string& field, const std::string& where, int64_t low,
                        int64_t high) {
  const nlohmann::json& value = require(object, field, where);
  if (!value.is_number_integer())
    throw JsonError(where + ": field '" + field + "' must be an integer, not " +
                    (value.is_number() ? std::string("a fraction") : std::string(value.type_name())));
  if (value.is_number_unsigned() && value.get<uint64_t>() > uint64_t(INT64_MAX))
    throw JsonError(where + ": field '" + field + "' is too large");
  const int64_t integer = value.get<int64_t>();
  if (integer < low || integer > high)
    throw JsonError(where + ": field '" + field + "' must be in [" + std::to_string(low) + ", " +
                    std::to_string(high) + "], is " + std::to_string(integer));
  return integer;
}

uint64_t require_unsigned(const nlohmann::json& object, const std::string& field, const std::string& where) {
  const nlohmann::json& value = require(object, field, where);
  if (value.is_number_unsigned()) return value.get<uint64_t>();
  if (value.is_number_integer()) throw JsonError(where + ": field '" + field + "' must not be negative");
  // A float is refused even when whole: 1e300 does not fit, and converting it would be undefined.
  throw JsonError(where + ": field '" + field + "' must be a non-negative integer, not " +
                  (value.is_number() ? "the number " + value.dump() : std::string(value.type_name())));
}

const nlohmann::json& require_object(const nlohmann::json& object, const std::string& field, const std::string& where) {
  const nlohmann::json& value = require(object, field, where);
  if (!value.is_object()) throw JsonError(where + ": field '" + field + "' must be an object, not " + value.type_name());
  return value;
}

void reject_unknown_fields(const nlohmann::json& object, std::initializer_list<const char*> known,
                           const std::string& where) {
  if (!object.is_object()) throw JsonError(where + ": expected an object, not " + std::string(object.type_name()));
  for (const auto& [key, value] : object.items()) {
    bool is_known = false;
    for (const char* name : known) is_known = is_known || key == name;
    if (is_known) continue;
    std::string list;
    for (const char* name : known) list += std::string(list.empty() ? "" : ", ") + name;
    throw JsonError(where + ": unknown field '" + key + "' (known: " + list + ")");
  }
}

nlohmann::json to_json(const Eigen::Vector2d& v) { return {v.x(), v.y()}; }
nlohmann::json to_json(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }
nlohmann::json to_json(const Eigen::Vector3f& v) { return {v.x(), v.y(), v.z()}; }

}  // namespace rt::config
