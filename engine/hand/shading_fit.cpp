#include "hand/shading_fit.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>

#include "hand/appearance_adaption.h"

namespace rt::hand {
namespace {

// Ridge on every term but the constant: with few pixels, or normals that all point one way, the
// directional terms are not determined, and then the fit falls back towards a flat shade instead
// of an arbitrary light.
constexpr double kRidge = 1e-2;
// Below this mean shade over the fitted pixels the estimate says the hand is black: not usable.
constexpr double kLeastMeanShade = 0.05;

}  // namespace

ShadingVector shading_basis(const Eigen::Vector3d& n) {
  ShadingVector b;
  b << 1.0, n.x(), n.y(), n.z(), n.x() * n.y(), n.x() * n.z(), n.y() * n.z(), n.x() * n.x() - n.y() * n.y(),
      3.0 * n.z() * n.z() - 1.0;
  return b;
}

void ShadingSums::add(const Eigen::Vector3d& unit_normal, double y) {
  const ShadingVector b = shading_basis(unit_normal);
  count += 1;
  normal += b * b.transpose();
  rhs += b * y;
}

ShadingSums& ShadingSums::operator+=(const ShadingSums& other) {
  count += other.count;
  normal += other.normal;
  rhs += other.rhs;
  return *this;
}

ShadingSums add_shading_partials(std::span<const shader_abi::ShadingPartial> partials) {
  ShadingSums sums;
  auto term = [](const shader_abi::ShadingPartial& p, int t) { return double(p.sums[size_t(t / 4)][size_t(t % 4)]); };
  for (const auto& partial : partials) {
    sums.count += term(partial, 0);
    int t = 1;
    for (int r = 0; r < kShadingTerms; ++r)
      for (int c = r; c < kShadingTerms; ++c) {
        const double value = term(partial, t++);
        sums.normal(r, c) += value;
        if (c != r) sums.normal(c, r) += value;
      }
    for (int k = 0; k < kShadingTerms; ++k) sums.rhs[k] += term(partial, 1 + RT_SHADING_MATRIX_TERMS + k);
  }
  return sums;
}

ShadingVector unlit_shading() {
  ShadingVector c = ShadingVector::Zero();
  c[0] = 1.0;
  return c;
}

std::array<std::array<float, 4>, 3> raster_shading(const ShadingVector& coefficients) {
  std::array<std::array<float, 4>, 3> out{};
  for (int k = 0; k < kShadingTerms; ++k) out[size_t(k / 4)][size_t(k % 4)] = float(coefficients[k]);
  return out;
}

double shade(const ShadingVector& coefficients, const Eigen::Vector3d& normal) {
  const double length_sq = normal.squaredNorm();
  if (!std::isfinite(length_sq) || length_sq <= 1e-12) return 1.0;
  const double s = coefficients.dot(shading_basis(normal / std::sqrt(length_sq)));
  return std::isfinite(s) ? std::clamp(s, RT_HAND_SHADE_MIN, RT_HAND_SHADE_MAX) : 1.0;
}

ShadingFit::ShadingFit(double smoothing, double min_pixels) : smoothing_(smoothing), min_pixels_(std::max(min_pixels, 1.0)) {}

bool ShadingFit::add_frame(const ShadingSums& frame) {
  if (!(frame.count >= min_pixels_)) return false;
  if (!frame.normal.allFinite() || !frame.rhs.allFinite()) return false;
  const double w = appearance_weight(double(frames_), smoothing_);
  mean_normal_ += w * (frame.normal / frame.count - mean_normal_);
  mean_rhs_ += w * (frame.rhs / frame.count - mean_rhs_);
  ++frames_;
  return true;
}

void ShadingFit::reset() {
  frames_ = 0;
  mean_normal_.setZero();
  mean_rhs_.setZero();
}

namespace {

struct Solved {
  ShadingVector raw;  // before normalising
  double mean = 0, sigma = 0, geometric_mean = 0;
};

std::optional<Solved> solve(const ShadingMatrix& normal, const ShadingVector& rhs) {
  ShadingMatrix regularised = normal;
  for (int k = 1; k < kShadingTerms; ++k) regularised(k, k) += kRidge;
  const Eigen::LDLT<ShadingMatrix> ldlt(regularised);
  if (ldlt.info() != Eigen::Success) return std::nullopt;
  Solved out;
  out.raw = ldlt.solve(rhs);
  if (!out.raw.allFinite()) return std::nullopt;
  // Moments of the shade over the fitted pixels, from the same sums: E[b] is the matrix's first
  // column (b_0 = 1), E[s^2] = c^T E[b b^T] c.
  out.mean = out.raw.dot(normal.col(0));
  const double variance = std::max(out.raw.dot(normal * out.raw) - out.mean * out.mean, 0.0);
  out.sigma = std::sqrt(variance);
  if (!(out.mean >= kLeastMeanShade) || !std::isfinite(variance)) return std::nullopt;
  // The geometric mean to second order in the spread (exp E[log s] ~ m exp(-var / 2 m^2)).
  out.geometric_mean = out.mean * std::exp(-variance / (2.0 * out.mean * out.mean));
  return out;
}

}  // namespace

ShadingVector ShadingFit::coefficients() const {
  if (frames_ == 0) return unlit_shading();
  const std::optional<Solved> solved = solve(mean_normal_, mean_rhs_);
  if (!solved) return unlit_shading();
  return solved->raw / solved->geometric_mean;
}

nlohmann::json ShadingFit::to_json() const {
  nlohmann::json out = {{"frames", frames_}};
  const std::optional<Solved> solved = frames_ > 0 ? solve(mean_normal_, mean_rhs_) : std::nullopt;
  out["state"] = frames_ == 0 ? "unlit, waiting" : solved ? "fitted" : "unlit, fit not usable";
  const ShadingVector c = coefficients();
  out["coefficients"] = std::vector<double>(c.data(), c.data() + kShadingTerms);
  if (solved) out["relative_spread"] = solved->sigma / solved->mean;
  return out;
}

}  // namespace rt::hand
