#include "calibration/tracker_calibration.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <random>

#include "calibration/calibration_error.h"
#include "calibration/rigid_alignment.h"
#include "config/json.h"

namespace rt::calibration {
namespace {

constexpr double kMillimetre = 1e-3;
// Every triple is tried up to this many (a 5x5 grid has 2300); beyond, as many random ones.
constexpr size_t kMaxHypotheses = 20000;
// A triple this close to a line proposes a rotation that the noise decides; it is skipped.
constexpr double kMinTripleSpreadM = 0.01;
constexpr int kMaxRefinements = 20;

struct Consensus {
  std::vector<bool> inlier;
  size_t count = 0;
  double residual_sum = 0;  // over the inliers; breaks ties between equally large consensus sets

  bool better_than(const Consensus& other) const {
    return count > other.count || (count == other.count && residual_sum < other.residual_sum);
  }
};

struct Points {
  std::vector<Eigen::Vector3d> tracker_m, site_m;
};

Consensus consensus_of(const Eigen::Isometry3d& site_from_tracker, const Points& points, double threshold_m) {
  Consensus consensus;
  consensus.inlier.resize(points.site_m.size());
  for (size_t i = 0; i < points.site_m.size(); ++i) {
    const double residual = (points.site_m[i] - site_from_tracker * points.tracker_m[i]).norm();
    consensus.inlier[i] = residual <= threshold_m;
    if (consensus.inlier[i]) {
      ++consensus.count;
      consensus.residual_sum += residual;
    }
  }
  return consensus;
}

std::vector<size_t> indices_of(const std::vector<bool>& inlier) {
  std::vector<size_t> indices;
  for (size_t i = 0; i < inlier.size(); ++i)
    if (inlier[i]) indices.push_back(i);
  return indices;
}

Points subset_of(const Points& points, const std::vector<size_t>& indices) {
  Points chosen;
  for (size_t i : indices) {
    chosen.tracker_m.push_back(points.tracker_m[i]);
    chosen.site_m.push_back(points.site_m[i]);
  }
  return chosen;
}

std::vector<std::array<size_t, 3>> minimal_sets(size_t count) {
  std::vector<std::array<size_t, 3>> sets;
  if (count * (count - 1) * (count - 2) / 6 <= kMaxHypotheses) {
    for (size_t a = 0; a < count; ++a)
      for (size_t b = a + 1; b < count; ++b)
        for (size_t c = b + 1; c < count; ++c) sets.push_back({a, b, c});
    return sets;
  }
  std::mt19937 rng(20230301);  // fixed: the same touches give the same calibration
  std::uniform_int_distribution<size_t> pick(0, count - 1);
  while (sets.size() < kMaxHypotheses) {
    const size_t a = pick(rng), b = pick(rng), c = pick(rng);
    if (a != b && b != c && a != c) sets.push_back({a, b, c});
  }
  return sets;
}

Consensus best_consensus(const Points& points, double threshold_m) {
  Consensus best;
  for (const auto& set : minimal_sets(points.site_m.size())) {
    const Points triple = subset_of(points, {set.begin(), set.end()});
    if (off_line_spread(triple.site_m) < kMinTripleSpreadM || off_line_spread(triple.tracker_m) < kMinTripleSpreadM)
      continue;
    const RigidFit fit = fit_rigid(triple.tracker_m, triple.site_m, "a triple of touches", kMinTripleSpreadM);
    const Consensus candidate = consensus_of(fit.target_from_source, points, threshold_m);
    if (candidate.better_than(best)) best = candidate;
  }
  return best;
}

std::string text(double value, int decimals = 1) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.*f", decimals, value);
  return buffer;
}

}  // namespace

size_t TrackerCalibration::inlier_count() const { return size_t(std::count(inlier.begin(), inlier.end(), true)); }

TrackerCalibration calibrate_tracker(const std::vector<TrackerTouch>& touches, double inlier_threshold_mm) {
  if (touches.size() < 3)
    throw CalibrationError("tracker calibration needs at least 3 touches (a grid across the screen is best), have " +
                           std::to_string(touches.size()));
  if (!std::isfinite(inlier_threshold_mm) || inlier_threshold_mm <= 0)
    throw CalibrationError("the inlier threshold must be a positive number of millimetres");
  Points points;
  for (const TrackerTouch& touch : touches) {
    if (!touch.site_m.allFinite() || !touch.tip_mm.allFinite())
      throw CalibrationError("touch '" + touch.label + "' has a non-finite coordinate");
    points.site_m.push_back(touch.site_m);
    points.tracker_m.push_back(touch.tip_mm * kMillimetre);
  }
  for (const auto& [set, name] : {std::pair{&points.site_m, "screen points"}, std::pair{&points.tracker_m, "fingertips"}})
    if (off_line_spread(*set) < kMinOffLineSpreadM)
      throw CalibrationError(std::string("the touches' ") + name + " lie on a line (or are in the wrong unit: screen "
                             "points in metres, fingertips in millimetres), so the rotation about it is unknown; touch "
                             "a grid that spans the screen both across and up");

  const double threshold_m = inlier_threshold_mm * kMillimetre;
  const size_t needed = std::max<size_t>(3, (touches.size() + 1) / 2);
  Consensus consensus = best_consensus(points, threshold_m);
  TrackerCalibration calibration;
  for (int round = 0; round < kMaxRefinements && consensus.count >= needed; ++round) {
    const Points agreeing = subset_of(points, indices_of(consensus.inlier));
    calibration.site_from_tracker =
        fit_rigid(agreeing.tracker_m, agreeing.site_m, "the touches that agree").target_from_source;
    const Consensus refined = consensus_of(calibration.site_from_tracker, points, threshold_m);
    const bool settled = refined.inlier == consensus.inlier;
    consensus = refined;
    if (settled) break;
  }
  if (consensus.count < needed)
    throw CalibrationError("only " + std::to_string(consensus.count) + " of " + std::to_string(touches.size()) +
                           " touches agree on one tracker pose within " + text(inlier_threshold_mm) + " mm (" +
                           std::to_string(needed) +
                           " needed): are the fingertips in the same order as the screen points, in millimetres, "
                           "and in a right-handed tracker space?");
  calibration.inlier = consensus.inlier;
  double squared_sum = 0;
  for (size_t i = 0; i < touches.size(); ++i) {
    const double residual = (points.site_m[i] - calibration.site_from_tracker * points.tracker_m[i]).norm();
    calibration.residuals_mm.push_back(residual / kMillimetre);
    if (calibration.inlier[i]) squared_sum += residual * residual;
  }
  calibration.inlier_rms_mm = std::sqrt(squared_sum / double(consensus.count)) / kMillimetre;
  // A flat grid fits a mirrored (left-handed) tip set just as well, by turning the tracker
  // over to the far side of the screen; the real tracker sits on the user's side.
  if (!(calibration.site_from_tracker.translation().z() > 0.0))
    throw CalibrationError("the tracker would sit behind the screen (z = " +
                           text(calibration.site_from_tracker.translation().z() * 1000.0, 0) +
                           " mm): the fingertips look mirrored; is the tracker space right-handed (Leap: +x right, "
                           "+y up, +z towards the user)?");
  if (!calibration.site_from_tracker.matrix().allFinite() || !std::isfinite(calibration.inlier_rms_mm))
    throw CalibrationError("the tracker calibration produced a non-finite result");
  return calibration;
}

std::vector<TrackerTouch> read_tracker_touches(const std::filesystem::path& path) {
  const std::string where = "tracker touches '" + path.string() + "'";
  const nlohmann::json json = config::read_json_file(path);
  std::vector<TrackerTouch> touches;
  for (const nlohmann::json& entry : config::require_array(json, "touches", where)) {
    TrackerTouch touch;
    touch.label = entry.contains("label") ? config::require_string(entry, "label", where + " touch")
                                          : "touch " + std::to_string(touches.size() + 1);
    const std::string touch_where = where + " touch '" + touch.label + "'";
    auto vector_of = [&](const char* field) {
      const nlohmann::json& list = config::require_array(entry, field, touch_where, 3, 3);
      Eigen::Vector3d v;
      for (int i = 0; i < 3; ++i) {
        if (!list[size_t(i)].is_number())
          throw config::JsonError(touch_where + ": field '" + field + "' must hold 3 numbers");
        v(i) = list[size_t(i)].get<double>();
      }
      return v;
    };
    touch.site_m = vector_of("site_m");
    touch.tip_mm = vector_of("tip_mm");
    touches.push_back(std::move(touch));
  }
  return touches;
}

nlohmann::json tracker_touches_to_json(const std::vector<TrackerTouch>& touches) {
  nlohmann::json list = nlohmann::json::array();
  for (const TrackerTouch& touch : touches)
    list.push_back({{"label", touch.label},
                    {"site_m", {touch.site_m.x(), touch.site_m.y(), touch.site_m.z()}},
                    {"tip_mm", {touch.tip_mm.x(), touch.tip_mm.y(), touch.tip_mm.z()}}});
  return {{"touches", list}};
}

}  // namespace rt::calibration
