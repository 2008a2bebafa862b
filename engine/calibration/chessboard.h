#pragma once
// The planar chessboard target: its grid of inner corners, their positions on the board, and
// finding them in a photograph to sub-pixel accuracy (Zhang's method needs only these).
#include <opencv2/core.hpp>

#include <optional>
#include <string>
#include <vector>

namespace rt::calibration {

struct Chessboard {
  int cols = 0;  // inner corners along a row (OpenCV's pattern width)
  int rows = 0;  // inner corners along a column (OpenCV's pattern height)
  double square_m = 0;

  cv::Size pattern_size() const { return {cols, rows}; }
  size_t corner_count() const { return size_t(cols) * size_t(rows); }
  // In OpenCV's corner order: row by row from the first corner, on the board plane z = 0.
  std::vector<cv::Point3f> object_points() const;
  // A board whose corner counts have the same parity looks the same after a half-turn, so
  // two cameras may number its corners from opposite ends: fatal when poses are chained.
  bool same_after_half_turn() const { return cols % 2 == rows % 2; }
  std::string describe() const;  // "9x6 inner corners, 25 mm squares"
};

// `inner_corners` is "COLSxROWS" (e.g. "9x6"), `square_m` the square's side in metres; the
// error says which part is wrong and what is expected.
Chessboard parse_chessboard(const std::string& inner_corners, double square_m);

// The board's corners in OpenCV's order, refined to sub-pixel accuracy; empty when the whole
// board is not visible. `gray` is an 8-bit single-channel image.
std::optional<std::vector<cv::Point2f>> find_chessboard(const cv::Mat& gray, const Chessboard& board);

}  // namespace rt::calibration
