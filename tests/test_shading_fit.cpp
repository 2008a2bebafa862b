// Appearance adaption's light estimate on the CPU (hand/shading_fit.h): a shade inside the basis
// is recovered up to the ridge's pull towards flat (2e-2 in direction, 5e-2 in shade),
// normalised to a geometric mean of 1 over the pixels (to second order: 1e-2 for a mild light); normals that all point one way give a flat, finite shade;
// frames fold as Eq. 3's do (counted, never timed); frames with too few pixels or non-finite
// sums are not counted; a fit that says the hand is black falls back to unlit.
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <random>

#include "hand/shading_fit.h"

using namespace rt;
using hand::ShadingSums;
using hand::ShadingVector;

namespace {

Eigen::Vector3d random_unit_shading_fit(std::mt19937& rng) {
  std::normal_distribution<double> gauss;
  const Eigen::Vector3d n(gauss(rng), gauss(rng), gauss(rng));
  return n.normalized();
}

ShadingVector mild_light() {
  ShadingVector c;
  c << 1.0, 0.1, 0.2, -0.15, 0.03, -0.05, 0.04, 0.06, -0.03;
  return c;
}

// A frame whose brightness ratio is exactly `scale` times the shade c.b(n), over normals from the
// whole sphere.
ShadingSums frame_of(const ShadingVector& c, double scale, int pixels, std::mt19937& rng) {
  ShadingSums sums;
  for (int i = 0; i < pixels; ++i) {
    const Eigen::Vector3d n = random_unit_shading_fit(rng);
    sums.add(n, scale * c.dot(hand::shading_basis(n)));
  }
  return sums;
}

}  // namespace

TEST_CASE("The light estimate recovers a shade inside its basis, normalised") {
  std::mt19937 rng(3);
  hand::ShadingFit fit(0.25, 16);
  CHECK(fit.coefficients() == hand::unlit_shading());
  REQUIRE(fit.add_frame(frame_of(mild_light(), 0.7, 4000, rng)));
  const ShadingVector c = fit.coefficients();
  // Up to the normalisation and the ridge's small pull towards flat: the direction of c.
  const ShadingVector expected = mild_light().normalized();
  CHECK((c.normalized() - expected).norm() < 2e-2);
  // Geometric mean over the pixels close to 1.
  double log_sum = 0;
  const int samples = 4000;
  for (int i = 0; i < samples; ++i) log_sum += std::log(hand::shade(c, random_unit_shading_fit(rng)));
  CHECK(std::exp(log_sum / samples) == Approx(1.0).margin(1e-2));
  CHECK(fit.frames() == 1);
  const nlohmann::json json = fit.to_json();
  CHECK(json["state"] == "fitted");
  CHECK(json["coefficients"].size() == 9);
}

TEST_CASE("The light estimate's shade, apart from its scale, follows the true one over the sphere") {
  std::mt19937 rng(4);
  hand::ShadingFit fit(1.0, 16);
  REQUIRE(fit.add_frame(frame_of(mild_light(), 1.0, 20000, rng)));
  const ShadingVector c = fit.coefficients();
  double worst = 0;
  for (int i = 0; i < 500; ++i) {
    const Eigen::Vector3d n = random_unit_shading_fit(rng);
    worst = std::max(worst, std::abs(hand::shade(c, n) / c[0] - mild_light().dot(hand::shading_basis(n)) / mild_light()[0]));
  }
  CHECK(worst < 0.05);
}

TEST_CASE("The light estimate's hard cases: one normal, too few pixels, NaN, a black fit, the clamp") {
  std::mt19937 rng(9);
  hand::ShadingFit fit(0.25, 16);
  SECTION("every normal the same: flat and finite") {
    ShadingSums sums;
    for (int i = 0; i < 100; ++i) sums.add(Eigen::Vector3d::UnitY(), 0.8);
    REQUIRE(fit.add_frame(sums));
    const ShadingVector c = fit.coefficients();
    REQUIRE(c.allFinite());
    CHECK(hand::shade(c, Eigen::Vector3d::UnitY()) == Approx(1.0).margin(1e-3));
  }
  SECTION("too few pixels") {
    CHECK_FALSE(fit.add_frame(frame_of(mild_light(), 1.0, 15, rng)));
    CHECK(fit.frames() == 0);
  }
  SECTION("NaN or infinite sums") {
    ShadingSums sums = frame_of(mild_light(), 1.0, 100, rng);
    sums.rhs[3] = std::numeric_limits<double>::quiet_NaN();
    CHECK_FALSE(fit.add_frame(sums));
    sums = frame_of(mild_light(), 1.0, 100, rng);
    sums.normal(2, 2) = std::numeric_limits<double>::infinity();
    CHECK_FALSE(fit.add_frame(sums));
    CHECK(fit.coefficients() == hand::unlit_shading());
  }
  SECTION("a fit that says the hand is black") {
    REQUIRE(fit.add_frame(frame_of(mild_light(), -1.0, 100, rng)));
    CHECK(fit.coefficients() == hand::unlit_shading());
    CHECK(fit.to_json()["state"] == "unlit, fit not usable");
  }
  SECTION("the shade is clamped, and a degenerate normal is unlit") {
    ShadingVector harsh = hand::unlit_shading() * 10.0;
    CHECK(hand::shade(harsh, Eigen::Vector3d::UnitX()) == RT_HAND_SHADE_MAX);
    CHECK(hand::shade(-harsh, Eigen::Vector3d::UnitX()) == RT_HAND_SHADE_MIN);
    CHECK(hand::shade(mild_light(), Eigen::Vector3d::Zero()) == 1.0);
    CHECK(hand::shade(mild_light(), Eigen::Vector3d(std::nan(""), 0, 0)) == 1.0);
  }
  SECTION("reset forgets") {
    REQUIRE(fit.add_frame(frame_of(mild_light(), 1.0, 100, rng)));
    fit.reset();
    CHECK(fit.frames() == 0);
    CHECK(fit.coefficients() == hand::unlit_shading());
  }
}

TEST_CASE("The light estimate folds frames as Eq. 3 does: counted, the running mean first") {
  std::mt19937 rng(12);
  ShadingVector other = mild_light();
  other[2] = -0.2;
  // Two frames with weight 1/2 each (smoothing below 1/2): the mean of their equations.
  hand::ShadingFit two(0.1, 16);
  const ShadingSums a = frame_of(mild_light(), 1.0, 3000, rng), b = frame_of(other, 1.0, 3000, rng);
  REQUIRE(two.add_frame(a));
  REQUIRE(two.add_frame(b));
  ShadingSums both = a;
  both += b;
  hand::ShadingFit pooled(0.1, 16);
  REQUIRE(pooled.add_frame(both));
  CHECK((two.coefficients() - pooled.coefficients()).norm() < 1e-9);
  // With smoothing 1, the last frame alone.
  hand::ShadingFit last(1.0, 16), only_b(1.0, 16);
  REQUIRE(last.add_frame(a));
  REQUIRE(last.add_frame(b));
  REQUIRE(only_b.add_frame(b));
  CHECK((last.coefficients() - only_b.coefficients()).norm() < 1e-9);
}
