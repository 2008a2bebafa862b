#pragma once
// Color spaces of appearance adaption (paper Eq. 3) and of its evaluation. Inputs are linear
// RGB in [0, 1] (the simulator's albedo, the renders); shaders/common/lab_alpha_beta.glsl is the
// GPU side of the L-alpha-beta transform and must stay in step with this file.
#include <Eigen/Core>

namespace rt::hand {

// Reinhard et al. 2001: RGB -> LMS -> log10 -> decorrelated L, alpha, beta. LMS is floored at
// kMinLms before the logarithm, so black maps to a finite color instead of -Inf.
inline constexpr double kMinLms = 1e-4;
Eigen::Vector3d rgb_to_lab_alpha_beta(const Eigen::Vector3d& rgb);
Eigen::Vector3d lab_alpha_beta_to_rgb(const Eigen::Vector3d& lab);  // not clamped

// CIE 1976 L*a*b* of linear sRGB primaries under D65.
Eigen::Vector3d rgb_to_cielab(const Eigen::Vector3d& linear_rgb);
double delta_e_76(const Eigen::Vector3d& lab1, const Eigen::Vector3d& lab2);
// CIEDE2000 (Sharma, Wu, Dalal 2005), k_L = k_C = k_H = 1.
double delta_e_2000(const Eigen::Vector3d& lab1, const Eigen::Vector3d& lab2);

// Eq. 3 for one channel: c' = min(sigma_i / max(sigma_g, sigma_floor), max_contrast) (c - m_g) + m_i.
// The cap keeps the template's own texture detail from being stretched to the portrait's spread,
// which comes mostly from shading the unlit mesh does not have.
struct ChannelStats {
  double mean = 0, sigma = 0;
};
double transfer_channel(double c, const ChannelStats& image, const ChannelStats& geometry, double sigma_floor,
                        double max_contrast);

}  // namespace rt::hand
