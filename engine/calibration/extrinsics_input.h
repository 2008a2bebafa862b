#pragma once
// The input of `remotetouch calibrate extrinsics`: the board, the cameras with their
// intrinsics and measured distances to the screen corners, and the simultaneous views.
//
// {"board": {"inner_corners": "9x6", "square_m": 0.025},
//  "screen": {"width_m": 1.439, "height_m": 0.809},          (optional: the 65-inch panel)
//  "reference_camera": "top-centre",                         (optional: the first camera)
//  "cameras": [{"name": "top-left",
//               "intrinsics": "intrinsics/top-left.json",    (a file from `calibrate intrinsics`, or the object)
//               "screen_corner_distances_m": {"top_left": 0.21, "top_right": 1.55,
//                                             "bottom_right": 1.72, "bottom_left": 0.83}}, ...],
//  "views": [{"name": "view-00",
//             "cameras": {"top-left": {"image": "views/00/top-left.png"},
//                         "top-centre": {"corners_px": [[x, y], ...]}}}, ...]}
//
// With `calibrate extrinsics --views-from REC` the views come from a recording of the site's
// cameras instead (devices/camera/recorded_board_views.h): "views" may then be left out, and so
// may a camera's "intrinsics", for which its device's factory calibration is taken.
//
// Relative paths are relative to the input file's folder. A distance is from the camera's
// optical centre (the lens) to the corner of the screen's active area, in metres; corners are
// named as the seated user sees the screen.
#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>
#include <vector>

#include "calibration/camera_network.h"
#include "calibration/chessboard.h"
#include "calibration/screen_trilateration.h"
#include "geometry/camera.h"
#include "geometry/site_frames.h"

namespace rt::calibration {

struct CameraSetup {
  std::string name;
  CameraIntrinsics intrinsics;
  bool intrinsics_given = true;  // false: to be taken from the recording of the views
  CornerDistances corner_distances_m{};
};

struct ExtrinsicsInput {
  Chessboard board;
  Screen screen;
  std::string reference_camera;
  std::vector<CameraSetup> cameras;
  std::vector<BoardSnapshot> snapshots;
  std::vector<std::string> board_not_found;  // "view 'v', camera 'c': path" for each image without the board
};

enum class ViewsFrom { Input, Recording };

// Reads the file, the intrinsics files it names and its images (finding the board in each).
// Errors name the file and the field.
ExtrinsicsInput read_extrinsics_input(const std::filesystem::path& path, ViewsFrom views_from = ViewsFrom::Input);
ExtrinsicsInput extrinsics_input_from_json(const nlohmann::json& json, const std::filesystem::path& base_folder,
                                           const std::string& where, ViewsFrom views_from = ViewsFrom::Input);
// Writes every camera's intrinsics inline and every view as corners_px.
nlohmann::json extrinsics_input_to_json(const ExtrinsicsInput& input);

}  // namespace rt::calibration
