#pragma once
// Appearance adaption's light estimate: the geometry hand's shading fitted to the portrait. The
// template's texture is albedo, while the remote cameras see the hand lit, brighter where it
// faces the light; Eq. 3's transfer matches the colors' means and spreads but not where on the
// hand each shade falls. The shading is the smooth function of the normal that distant light
// gives, nine spherical-harmonic terms (shared/hand_shading.h), fitted by least squares to the
// portrait's brightness over the template's on Eq. 3's pixels (passes/hand_shading_stats.h sums
// the normal equations on the GPU; this adds the workgroups' sums, folds frames together as
// Eq. 3 does and solves). The light is fixed in the remote site's frame, where the normals are,
// so every frame refines one estimate. Owns no Vulkan objects.
//
// The shade is normalised to a geometric mean of 1 over the fitted pixels: Eq. 3 already matched
// the mean of the log-brightness (L of L-alpha-beta) to the portrait's, and the shade must move
// light between pixels, not change that mean.
#include <Eigen/Core>
#include <array>
#include <optional>
#include <span>

#include <nlohmann/json.hpp>

#include "shared/hand_shading.h"

namespace rt::hand {

inline constexpr int kShadingTerms = RT_SHADING_TERMS;
using ShadingVector = Eigen::Matrix<double, kShadingTerms, 1>;
using ShadingMatrix = Eigen::Matrix<double, kShadingTerms, kShadingTerms>;

// b(n) of shared/hand_shading.h (common/shading_basis.glsl is its GPU side).
ShadingVector shading_basis(const Eigen::Vector3d& unit_normal);

// The normal equations of one frame: sum b b^T, sum b y and the pixel count.
struct ShadingSums {
  double count = 0;
  ShadingMatrix normal = ShadingMatrix::Zero();
  ShadingVector rhs = ShadingVector::Zero();
  void add(const Eigen::Vector3d& unit_normal, double y);  // one pixel (the reference's way)
  ShadingSums& operator+=(const ShadingSums& other);
};
// The workgroups' partial sums added (hand_shading_stats's layout), in double precision.
ShadingSums add_shading_partials(std::span<const shader_abi::ShadingPartial> partials);

// The coefficients of an unlit hand: a shade of 1 everywhere.
ShadingVector unlit_shading();
// The push-constant form of c (HandRasterParams::shading).
std::array<std::array<float, 4>, 3> raster_shading(const ShadingVector& coefficients);
// sum c_k b_k(n), clamped as the raster clamps it; 1 for a normal that is not a unit vector.
double shade(const ShadingVector& coefficients, const Eigen::Vector3d& normal);

class ShadingFit {
 public:
  // `smoothing` and `min_pixels` as Eq. 3's (hand/appearance_adaption.h: appearance_weight).
  ShadingFit(double smoothing, double min_pixels);

  // Folds one frame in; a frame with fewer than min_pixels pixels, or sums that are not finite,
  // leaves the estimate as it was. Returns whether the frame counted.
  bool add_frame(const ShadingSums& frame);
  void reset();

  uint64_t frames() const { return frames_; }
  // The normalised coefficients, or unlit_shading() before any frame counted or when the
  // estimate is not usable (a shade that is not positive on average over the fitted pixels).
  ShadingVector coefficients() const;
  nlohmann::json to_json() const;  // frames, coefficients, the shade's spread over the pixels

 private:
  double smoothing_, min_pixels_;
  uint64_t frames_ = 0;
  ShadingMatrix mean_normal_ = ShadingMatrix::Zero();  // per pixel, smoothed over frames
  ShadingVector mean_rhs_ = ShadingVector::Zero();
};

}  // namespace rt::hand
