#include "calibration/extrinsics_input.h"

#include <algorithm>
#include <cmath>
#include <set>

#include "calibration/calibration_error.h"
#include "calibration/image_files.h"
#include "config/json.h"

namespace rt::calibration {
namespace {

using config::JsonError;

Chessboard board_from_json(const nlohmann::json& json, const std::string& where) {
  Chessboard board = parse_chessboard(config::require_string(json, "inner_corners", where),
                                      config::require_positive(json, "square_m", where));
  if (board.same_after_half_turn())
    throw CalibrationError(where + ": a " + std::to_string(board.cols) + "x" + std::to_string(board.rows) +
                           " board looks the same after a half-turn, so two cameras may number its corners from "
                           "opposite ends; use one odd and one even count (e.g. 9x6)");
  return board;
}

CameraIntrinsics intrinsics_of(const nlohmann::json& camera, const std::filesystem::path& base_folder,
                               const std::string& where) {
  const nlohmann::json& field = config::require(camera, "intrinsics", where);
  if (field.is_object()) return intrinsics_from_json(field, where + " intrinsics");
  if (!field.is_string())
    throw JsonError(where + ": field 'intrinsics' must be a file name or an object, not " + field.type_name());
  const std::filesystem::path path = base_folder / field.get<std::string>();
  return intrinsics_from_json(config::read_json_file(path), where + " intrinsics '" + path.string() + "'");
}

CornerDistances distances_of(const nlohmann::json& camera, const std::string& where) {
  const nlohmann::json& field = config::require(camera, "screen_corner_distances_m", where);
  const std::string inner = where + " screen_corner_distances_m";
  if (!field.is_object())
    throw JsonError(inner + ": must be an object with top_left, top_right, bottom_right, bottom_left (metres)");
  std::set<std::string> known;
  CornerDistances distances{};
  for (ScreenCorner corner : kScreenCorners) {
    if (!field.contains(corner_name(corner)))
      throw JsonError(inner + ": missing the distance to '" + corner_name(corner) +
                      "': all four corners are needed, the fourth catches a mis-measured one");
    distances[size_t(corner)] = config::require_positive(field, corner_name(corner), inner);
    known.insert(corner_name(corner));
  }
  for (const auto& item : field.items())
    if (!known.count(item.key()))
      throw JsonError(inner + ": unknown corner '" + item.key() + "' (top_left, top_right, bottom_right, bottom_left)");
  return distances;
}

std::vector<cv::Point2f> corners_of(const nlohmann::json& list, const std::string& where) {
  if (!list.is_array()) throw JsonError(where + ": field 'corners_px' must be an array of [x, y]");
  std::vector<cv::Point2f> corners;
  for (const nlohmann::json& point : list) {
    if (!point.is_array() || point.size() != 2 || !point[0].is_number() || !point[1].is_number())
      throw JsonError(where + ": corner " + std::to_string(corners.size()) + " must be [x, y] in pixels");
    const float x = point[0].get<float>(), y = point[1].get<float>();
    if (!std::isfinite(x) || !std::isfinite(y))
      throw JsonError(where + ": corner " + std::to_string(corners.size()) + " is not finite");
    corners.emplace_back(x, y);
  }
  return corners;
}

}  // namespace

ExtrinsicsInput extrinsics_input_from_json(const nlohmann::json& json, const std::filesystem::path& base_folder,
                                           const std::string& where, ViewsFrom views_from) {
  const bool from_recording = views_from == ViewsFrom::Recording;
  ExtrinsicsInput input;
  input.board = board_from_json(config::require(json, "board", where), where + " board");
  if (json.contains("screen")) {
    input.screen.width_m = config::require_positive(json["screen"], "width_m", where + " screen");
    input.screen.height_m = config::require_positive(json["screen"], "height_m", where + " screen");
  }
  for (const nlohmann::json& entry : config::require_array(json, "cameras", where, 1)) {
    CameraSetup camera;
    camera.name = config::require_string(entry, "name", where + " camera");
    const std::string camera_where = where + " camera '" + camera.name + "'";
    if (camera.name.empty()) throw JsonError(where + ": a camera has an empty name");
    camera.intrinsics_given = !from_recording || entry.contains("intrinsics");
    if (camera.intrinsics_given) camera.intrinsics = intrinsics_of(entry, base_folder, camera_where);
    camera.corner_distances_m = distances_of(entry, camera_where);
    input.cameras.push_back(std::move(camera));
  }
  input.reference_camera =
      json.contains("reference_camera") ? config::require_string(json, "reference_camera", where) : input.cameras[0].name;

  static const nlohmann::json no_views = nlohmann::json::array();
  const nlohmann::json& views =
      from_recording && !json.contains("views") ? no_views : config::require_array(json, "views", where, from_recording ? 0 : 1);
  for (const nlohmann::json& view : views) {
    BoardSnapshot snapshot;
    snapshot.name = view.contains("name") ? config::require_string(view, "name", where + " view")
                                          : "view " + std::to_string(input.snapshots.size());
    const std::string view_where = where + " view '" + snapshot.name + "'";
    const nlohmann::json& cameras = config::require(view, "cameras", view_where);
    if (!cameras.is_object()) throw JsonError(view_where + ": field 'cameras' must map camera names to observations");
    for (const auto& [camera_name, observation] : cameras.items()) {
      const std::string observation_where = view_where + " camera '" + camera_name + "'";
      const auto setup = std::find_if(input.cameras.begin(), input.cameras.end(),
                                      [&](const CameraSetup& c) { return c.name == camera_name; });
      if (setup == input.cameras.end()) throw JsonError(observation_where + ": no such camera in 'cameras'");
      if (observation.contains("corners_px")) {
        snapshot.observations.push_back({camera_name, corners_of(observation["corners_px"], observation_where)});
        continue;
      }
      const std::filesystem::path image_path =
          base_folder / config::require_string(observation, "image", observation_where + " (or 'corners_px')");
      if (!setup->intrinsics_given)
        throw JsonError(observation_where + ": an image needs the camera's 'intrinsics' in the input");
      const cv::Mat image = read_gray_image(image_path);
      const CameraIntrinsics& k = setup->intrinsics;
      if (image.cols != int(k.width) || image.rows != int(k.height))
        throw CalibrationError(observation_where + ": image '" + image_path.string() + "' is " +
                               std::to_string(image.cols) + "x" + std::to_string(image.rows) +
                               ", the camera's intrinsics are for " + std::to_string(k.width) + "x" +
                               std::to_string(k.height));
      if (auto corners = find_chessboard(image, input.board))
        snapshot.observations.push_back({camera_name, std::move(*corners)});
      else
        input.board_not_found.push_back("view '" + snapshot.name + "', camera '" + camera_name + "': " +
                                        image_path.string());
    }
    input.snapshots.push_back(std::move(snapshot));
  }
  return input;
}

ExtrinsicsInput read_extrinsics_input(const std::filesystem::path& path, ViewsFrom views_from) {
  return extrinsics_input_from_json(config::read_json_file(path), path.parent_path(),
                                    "extrinsics input '" + path.string() + "'", views_from);
}

nlohmann::json extrinsics_input_to_json(const ExtrinsicsInput& input) {
  nlohmann::json json;
  json["board"] = {{"inner_corners", std::to_string(input.board.cols) + "x" + std::to_string(input.board.rows)},
                   {"square_m", input.board.square_m}};
  json["screen"] = {{"width_m", input.screen.width_m}, {"height_m", input.screen.height_m}};
  json["reference_camera"] = input.reference_camera;
  json["cameras"] = nlohmann::json::array();
  for (const CameraSetup& camera : input.cameras) {
    nlohmann::json distances;
    for (ScreenCorner corner : kScreenCorners) distances[corner_name(corner)] = camera.corner_distances_m[size_t(corner)];
    json["cameras"].push_back({{"name", camera.name},
                               {"intrinsics", intrinsics_to_json(camera.intrinsics)},
                               {"screen_corner_distances_m", distances}});
  }
  json["views"] = nlohmann::json::array();
  for (const BoardSnapshot& snapshot : input.snapshots) {
    nlohmann::json cameras = nlohmann::json::object();
    for (const CameraObservation& observation : snapshot.observations) {
      nlohmann::json corners = nlohmann::json::array();
      for (const cv::Point2f& corner : observation.corners) corners.push_back({corner.x, corner.y});
      cameras[observation.camera] = {{"corners_px", corners}};
    }
    json["views"].push_back({{"name", snapshot.name}, {"cameras", cameras}});
  }
  return json;
}

}  // namespace rt::calibration
