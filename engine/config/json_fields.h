#pragma once
// Reading JSON documents (site descriptions, calibration, scenes) with errors that name the
// field and say what is wrong, e.g. "camera 'top-left': field 'fx' must be a number > 0".
#include <nlohmann/json.hpp>

#include <filesystem>
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

}  // namespace rt::config
