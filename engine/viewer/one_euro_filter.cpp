#include "viewer/one_euro_filter.h"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace rt {

namespace {

// Weight of the new sample in an exponential smoother with this cutoff, sampled after dt.
double smoothing_weight(double cutoff_hz, double dt_s) {
  const double time_constant = 1.0 / (2.0 * std::numbers::pi * cutoff_hz);
  return 1.0 / (1.0 + time_constant / dt_s);
}

}  // namespace

OneEuroFilter::OneEuroFilter(const OneEuroParameters& parameters) : parameters_(parameters) {
  if (!(parameters.min_cutoff_hz > 0 && parameters.derivative_cutoff_hz > 0 && parameters.speed_coefficient >= 0) ||
      !std::isfinite(parameters.min_cutoff_hz + parameters.derivative_cutoff_hz + parameters.speed_coefficient))
    throw std::invalid_argument("OneEuroParameters: cutoffs must be > 0 and the speed coefficient >= 0, all finite");
}

Eigen::Vector3d OneEuroFilter::update(const Eigen::Vector3d& value, double dt_s) {
  if (!value.allFinite()) throw std::invalid_argument("OneEuroFilter::update: the value holds a NaN or infinity");
  if (!initialised_) {
    reset(value);
    return value_;
  }
  if (!(dt_s > 0) || !std::isfinite(dt_s))
    throw std::invalid_argument("OneEuroFilter::update: dt must be > 0 and finite, got " + std::to_string(dt_s) + " s");
  const Eigen::Vector3d raw_velocity = (value - value_) / dt_s;
  velocity_ += smoothing_weight(parameters_.derivative_cutoff_hz, dt_s) * (raw_velocity - velocity_);
  const double cutoff = parameters_.min_cutoff_hz + parameters_.speed_coefficient * velocity_.norm();
  value_ += smoothing_weight(cutoff, dt_s) * (value - value_);
  return value_;
}

void OneEuroFilter::reset(const Eigen::Vector3d& value) {
  if (!value.allFinite()) throw std::invalid_argument("OneEuroFilter::reset: the value holds a NaN or infinity");
  initialised_ = true;
  value_ = value;
  velocity_.setZero();
}

}  // namespace rt
