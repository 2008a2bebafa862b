#include "sim/json_values.h"

#include <charconv>
#include <cmath>

#include "config/json_fields.h"

namespace rt::sim {

using config::JsonError;

namespace {

template <int N>
Eigen::Matrix<double, N, 1> require_vector(const nlohmann::json& object, const std::string& field,
                                           const std::string& where) {
  const nlohmann::json& array = config::require_array(object, field, where, N, N);
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
  const double value = config::require_number(object, field, where);
  if (value < low || value > high)
    throw JsonError(where + ": field '" + field + "' must be in [" + format_number(low) + ", " + format_number(high) +
                    "], is " + format_number(value));
  return value;
}

int64_t require_integer(const nlohmann::json& object, const std::string& field, const std::string& where, int64_t low,
                        int64_t high) {
  const nlohmann::json& value = config::require(object, field, where);
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
  const nlohmann::json& value = config::require(object, field, where);
  if (value.is_number_unsigned()) return value.get<uint64_t>();
  if (value.is_number_integer()) throw JsonError(where + ": field '" + field + "' must not be negative");
  throw JsonError(where + ": field '" + field + "' must be a non-negative integer, not " +
                  (value.is_number() ? std::string("a fraction") : std::string(value.type_name())));
}

const nlohmann::json& require_object(const nlohmann::json& object, const std::string& field, const std::string& where) {
  const nlohmann::json& value = config::require(object, field, where);
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

}  // namespace rt::sim
