#include "config/json_fields.h"

#include <cmath>
#include <fstream>

namespace rt::config {

nlohmann::json read_json_file(const std::filesystem::path& path) {
  std::ifstream file(path);
  if (!file) throw JsonError("cannot open '" + path.string() + "'");
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

}  // namespace rt::config
