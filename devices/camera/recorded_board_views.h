#pragma once
// `calibrate extrinsics --views-from REC`: the chessboard views taken from a recording of the
// site's own cameras (what `record` writes from live devices, a vendor's recorder, or RemoteTouch's
// recording format), so that a real installation needs no photographs taken by hand. The cameras'
// frame sets are already put together by device time, so the views of one set are simultaneous,
// which is what linking two cameras through the board needs.
#include <string>
#include <vector>

#include "calibration/extrinsics_input.h"
#include "sim/recorded_rgbd_source.h"

namespace rt::camera {

struct RecordedBoardViews {
  size_t frame_sets_searched = 0;
  size_t views_added = 0;  // frame sets in which at least one camera found the whole board
  // Per camera of the input: the frame sets searched in which it did not find the board.
  std::vector<size_t> board_missed;
};

// Searches the board in every camera's colour image of one frame set every `every_s` seconds of
// the recording (0: every set), adding a view for each set where a camera found it. A camera
// the input gives no intrinsics takes its recorded (factory) colour intrinsics. Throws
// calibration::CalibrationError when a camera of the input is not in the recording (naming those
// it has), when given intrinsics are for another image size, or when `every_s` is negative or
// not finite.
RecordedBoardViews add_recorded_board_views(calibration::ExtrinsicsInput& input, sim::RecordedRgbdSource& recording,
                                            double every_s, const std::string& where);

}  // namespace rt::camera
