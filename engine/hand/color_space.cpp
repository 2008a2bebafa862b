#include "hand/color_space.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <numbers>

namespace rt::hand {
namespace {

const Eigen::Matrix3d& rgb_to_lms() {
  static const Eigen::Matrix3d m = (Eigen::Matrix3d() << 0.3811, 0.5783, 0.0402, 0.1967, 0.7244, 0.0782, 0.0241, 0.1288,
                                    0.8444).finished();
  return m;
}
const Eigen::Matrix3d& log_lms_to_lab() {
  static const Eigen::Matrix3d m = (Eigen::DiagonalMatrix<double, 3>(1 / std::sqrt(3.0), 1 / std::sqrt(6.0), 1 / std::sqrt(2.0)) *
                                    (Eigen::Matrix3d() << 1, 1, 1, 1, 1, -2, 1, -1, 0).finished());
  return m;
}

double radians(double degrees) { return degrees * std::numbers::pi / 180.0; }
double degrees(double radians) { return radians * 180.0 / std::numbers::pi; }

}  // namespace

Eigen::Vector3d rgb_to_lab_alpha_beta(const Eigen::Vector3d& rgb) {
  Eigen::Vector3d lms = rgb_to_lms() * rgb;
  for (int c = 0; c < 3; ++c) lms[c] = std::log10(std::max(lms[c], kMinLms));
  return log_lms_to_lab() * lms;
}

Eigen::Vector3d lab_alpha_beta_to_rgb(const Eigen::Vector3d& lab) {
  static const Eigen::Matrix3d inverse = log_lms_to_lab().inverse();
  // The exact inverse of rgb_to_lms() (Reinhard et al. print it to four digits, which is off by
  // 0.4% on a round trip); the shader holds the same numbers.
  static const Eigen::Matrix3d lms_to_rgb = (Eigen::Matrix3d() << 4.4686699, -3.5886759, 0.1196044, -1.2197166, 2.3830879,
                                             -0.1626301, 0.0585085, -0.2610784, 1.2056659).finished();
  Eigen::Vector3d lms = inverse * lab;
  // Colors in [0, 1] have log10 LMS in [log10(kMinLms), 0]: clamping a little beyond keeps any
  // transfer, however extreme, from overflowing.
  for (int c = 0; c < 3; ++c) lms[c] = std::pow(10.0, std::clamp(lms[c], std::log10(kMinLms), 0.5));
  return lms_to_rgb * lms;
}

Eigen::Vector3d rgb_to_cielab(const Eigen::Vector3d& linear_rgb) {
  const Eigen::Matrix3d to_xyz = (Eigen::Matrix3d() << 0.4124564, 0.3575761, 0.1804375, 0.2126729, 0.7151522, 0.0721750,
                                  0.0193339, 0.1191920, 0.9503041).finished();
  const Eigen::Vector3d white(0.95047, 1.0, 1.08883);
  const Eigen::Vector3d xyz = to_xyz * linear_rgb.cwiseMax(0.0);
  auto f = [](double t) { return t > 216.0 / 24389.0 ? std::cbrt(t) : (24389.0 / 27.0 * t + 16.0) / 116.0; };
  const double fx = f(xyz.x() / white.x()), fy = f(xyz.y() / white.y()), fz = f(xyz.z() / white.z());
  return {116.0 * fy - 16.0, 500.0 * (fx - fy), 200.0 * (fy - fz)};
}

double delta_e_76(const Eigen::Vector3d& lab1, const Eigen::Vector3d& lab2) { return (lab1 - lab2).norm(); }

double delta_e_2000(const Eigen::Vector3d& lab1, const Eigen::Vector3d& lab2) {
  const double l1 = lab1.x(), a1 = lab1.y(), b1 = lab1.z(), l2 = lab2.x(), a2 = lab2.y(), b2 = lab2.z();
  const double c_bar = (std::hypot(a1, b1) + std::hypot(a2, b2)) / 2;
  const double c7 = std::pow(c_bar, 7);
  const double g = 0.5 * (1 - std::sqrt(c7 / (c7 + std::pow(25.0, 7))));
  const double a1p = (1 + g) * a1, a2p = (1 + g) * a2;
  const double c1p = std::hypot(a1p, b1), c2p = std::hypot(a2p, b2);
  auto hue = [](double b, double a) {
    if (a == 0 && b == 0) return 0.0;
    const double h = degrees(std::atan2(b, a));
    return h < 0 ? h + 360 : h;
  };
  const double h1p = hue(b1, a1p), h2p = hue(b2, a2p);
  const double dl = l2 - l1, dc = c2p - c1p;
  double dh = 0;
  if (c1p * c2p != 0) {
    dh = h2p - h1p;
    if (dh > 180) dh -= 360;
    else if (dh < -180) dh += 360;
  }
  const double dH = 2 * std::sqrt(c1p * c2p) * std::sin(radians(dh / 2));
  const double l_bar = (l1 + l2) / 2, cp_bar = (c1p + c2p) / 2;
  double h_bar = h1p + h2p;
  if (c1p * c2p != 0) {
    if (std::abs(h1p - h2p) <= 180) h_bar /= 2;
    else h_bar = h_bar < 360 ? (h_bar + 360) / 2 : (h_bar - 360) / 2;
  }
  const double t = 1 - 0.17 * std::cos(radians(h_bar - 30)) + 0.24 * std::cos(radians(2 * h_bar)) +
                   0.32 * std::cos(radians(3 * h_bar + 6)) - 0.20 * std::cos(radians(4 * h_bar - 63));
  const double d_theta = 30 * std::exp(-std::pow((h_bar - 275) / 25, 2));
  const double cp7 = std::pow(cp_bar, 7);
  const double r_c = 2 * std::sqrt(cp7 / (cp7 + std::pow(25.0, 7)));
  const double s_l = 1 + 0.015 * std::pow(l_bar - 50, 2) / std::sqrt(20 + std::pow(l_bar - 50, 2));
  const double s_c = 1 + 0.045 * cp_bar, s_h = 1 + 0.015 * cp_bar * t;
  const double r_t = -std::sin(radians(2 * d_theta)) * r_c;
  return std::sqrt(std::pow(dl / s_l, 2) + std::pow(dc / s_c, 2) + std::pow(dH / s_h, 2) + r_t * (dc / s_c) * (dH / s_h));
}

double transfer_channel(double c, const ChannelStats& image, const ChannelStats& geometry, double sigma_floor,
                        double max_contrast) {
  return std::min(image.sigma / std::max(geometry.sigma, sigma_floor), max_contrast) * (c - geometry.mean) + image.mean;
}

}  // namespace rt::hand
