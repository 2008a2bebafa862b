#pragma once
// The one error type of the calibration: bad input (files, measurements, degenerate
// geometry) and estimates that cannot be trusted. The message says what is wrong and,
// where it can, how to fix it; the command line prints it as "remotetouch: error: ...".
#include <stdexcept>

namespace rt::calibration {

class CalibrationError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace rt::calibration
