#include "sim/person_mesh.h"

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "sim/face.h"

namespace rt::sim {
namespace {

MeshVertex make_vertex(const Eigen::Vector3d& p, const Eigen::Vector3d& n, float part, const Eigen::Vector3f& color,
                       const Eigen::Vector3f& stripe_color, float stripe_period) {
  MeshVertex v{};
  v.position_part = {float(p.x()), float(p.y()), float(p.z()), part};
  v.normal_stripe = {float(n.x()), float(n.y()), float(n.z()), stripe_period};
  v.color = {color.x(), color.y(), color.z(), 1.0f};
  v.stripe_color = {stripe_color.x(), stripe_color.y(), stripe_color.z(), 1.0f};
  return v;
}

// Any unit vector orthogonal to `axis`, preferring the direction of `hint`.
Eigen::Vector3d orthogonal(const Eigen::Vector3d& axis, const Eigen::Vector3d& hint) {
  Eigen::Vector3d u = hint - hint.dot(axis) * axis;
  if (u.norm() < 1e-6) u = std::abs(axis.x()) < 0.9 ? Eigen::Vector3d::UnitX().cross(axis) : Eigen::Vector3d::UnitY().cross(axis);
  return u.normalized();
}

}  // namespace

void append_capsule(std::vector<MeshVertex>& mesh, const Eigen::Vector3d& a, const Eigen::Vector3d& b, double radius_u,
                    double radius_v, const Eigen::Vector3d& u_hint, float part, const Eigen::Vector3f& color,
                    const Eigen::Vector3f& stripe_color, float stripe_period_m, const MeshDetail& detail) {
  if (!a.allFinite() || !b.allFinite() || !(radius_u > 0) || !(radius_v > 0))
    throw std::invalid_argument("capsule with a non-finite end or a radius <= 0");
  const Eigen::Vector3d along = b - a;
  // A zero-length bone (the thumb's metacarpal) is a sphere: any axis will do.
  const Eigen::Vector3d axis = along.norm() > 1e-9 ? along.normalized() : Eigen::Vector3d::UnitY();
  const Eigen::Vector3d u = orthogonal(axis, u_hint), v = axis.cross(u);
  const int segments = std::max(3, detail.segments), rings = std::max(1, detail.rings);
  // Latitude from the pole at a (-pi/2) over the cylinder to the pole at b (+pi/2): the
  // equator ring appears twice, once at each end of the cylinder.
  struct Ring {
    double latitude;
    const Eigen::Vector3d* centre;
  };
  std::vector<Ring> latitudes;
  for (int r = 0; r <= rings; ++r) latitudes.push_back({-std::numbers::pi / 2 + std::numbers::pi / 2 * r / rings, &a});
  for (int r = 0; r <= rings; ++r) latitudes.push_back({std::numbers::pi / 2 * r / rings, &b});
  auto point = [&](const Ring& ring, int s, Eigen::Vector3d& normal) {
    const double angle = 2 * std::numbers::pi * s / segments;
    const double c = std::cos(ring.latitude), axial = std::sin(ring.latitude);
    const Eigen::Vector3d radial = std::cos(angle) * u * radius_u + std::sin(angle) * v * radius_v;
    // The normal of an ellipse is not its radial direction: scale by the other radius.
    normal = (std::cos(angle) * u * radius_v + std::sin(angle) * v * radius_u).normalized() * c + axis * axial;
    const double cap_radius = std::min(radius_u, radius_v);
    return Eigen::Vector3d(*ring.centre + radial * c + axis * axial * cap_radius);
  };
  for (size_t r = 0; r + 1 < latitudes.size(); ++r)
    for (int s = 0; s < segments; ++s) {
      Eigen::Vector3d n00, n01, n10, n11;
      const Eigen::Vector3d p00 = point(latitudes[r], s, n00), p01 = point(latitudes[r], s + 1, n01);
      const Eigen::Vector3d p10 = point(latitudes[r + 1], s, n10), p11 = point(latitudes[r + 1], s + 1, n11);
      for (const auto& [p, n] : {std::pair{p00, n00}, std::pair{p10, n10}, std::pair{p11, n11}, std::pair{p00, n00},
                                 std::pair{p11, n11}, std::pair{p01, n01}})
        mesh.push_back(make_vertex(p, n, part, color, stripe_color, stripe_period_m));
    }
}

void append_hand(std::vector<MeshVertex>& mesh, const HandSkeleton& hand, double hand_scale,
                 const Eigen::Vector3f& skin_rgb, const MeshDetail& detail) {
  const float part = float(RT_PART_HAND);
  const MeshDetail fine{std::max(8, detail.segments / 2), std::max(2, detail.rings / 2)};
  // Finger radii of a medium adult hand, thumb to pinky.
  const double radii[kDigitCount] = {0.0105, 0.0095, 0.0095, 0.009, 0.008};
  const Eigen::Vector3d normal = hand.palm_normal.norm() > 1e-9 ? hand.palm_normal.normalized() : Eigen::Vector3d::UnitZ();
  for (int d = 0; d < kDigitCount; ++d) {
    const double radius = radii[d] * hand_scale;
    for (int bone = 0; bone < kJointsPerDigit - 1; ++bone) {
      const Eigen::Vector3d& from = hand.digits[d][bone];
      const Eigen::Vector3d& to = hand.digits[d][bone + 1];
      // Metacarpals lie inside the palm; a thinner capsule keeps the palm's shape.
      const double r = bone == 0 ? radius * 0.9 : radius * (1.0 - 0.08 * bone);
      append_capsule(mesh, from, to, r, r, normal, part, skin_rgb, skin_rgb, 0.0f, fine);
    }
  }
  // The palm: flat, as wide as the knuckles, from the wrist to the middle knuckle.
  const Eigen::Vector3d knuckles = hand.joint(Digit::Middle, DigitJoint::Mcp);
  const double width = (hand.joint(Digit::Index, DigitJoint::Mcp) - hand.joint(Digit::Pinky, DigitJoint::Mcp)).norm();
  const Eigen::Vector3d across = (hand.joint(Digit::Index, DigitJoint::Mcp) - hand.joint(Digit::Pinky, DigitJoint::Mcp));
  append_capsule(mesh, hand.wrist, knuckles, std::max(0.6 * width, 0.02 * hand_scale), 0.013 * hand_scale, across, part,
                 skin_rgb, skin_rgb, 0.0f, fine);
}

void append_forearm(std::vector<MeshVertex>& mesh, const ArmPose& arm, const Eigen::Vector3f& skin_rgb,
                    const MeshDetail& detail) {
  append_capsule(mesh, arm.elbow, arm.wrist, kForearmRadiusM, kForearmRadiusM, Eigen::Vector3d::UnitX(), float(RT_PART_BODY),
                 skin_rgb, skin_rgb, 0.0f, detail);
}

void append_head(std::vector<MeshVertex>& mesh, const PersonPose& pose, const Eigen::Vector3f& skin_rgb,
                 const MeshDetail& detail) {
  const HeadShape shape = head_shape(pose.head_radius_m);
  const Eigen::Matrix3d& rotation = pose.head_rotation;
  const Eigen::Vector3d up = rotation * Eigen::Vector3d(0, shape.half_length_m, 0);
  const size_t first = mesh.size();
  append_capsule(mesh, pose.head_centre - up, pose.head_centre + up, shape.width_radius_m, shape.depth_radius_m,
                 rotation * Eigen::Vector3d::UnitX(), float(RT_PART_BODY), skin_rgb, skin_rgb, 0.0f, detail);
  // The face's texture coordinates are a linear function of the position, so interpolating them
  // over a triangle prints the photo exactly as the planar projection would.
  for (size_t i = first; i < mesh.size(); ++i) {
    MeshVertex& v = mesh[i];
    const Eigen::Vector3d site(v.position_part[0], v.position_part[1], v.position_part[2]);
    const Eigen::Vector3d head = rotation.transpose() * (site - pose.head_centre);
    const Eigen::Vector2d uv = face_uv(head);
    v.stripe_color = {float(uv.x()), float(uv.y()), float(face_facing(head, shape)), 1.0f};
    v.normal_stripe[3] = kFaceTexturePeriod;
  }
}

std::vector<MeshVertex> person_mesh(const PersonPose& pose, const UserAppearance& user, const MeshDetail& detail) {
  const float body = float(RT_PART_BODY);
  const Eigen::Vector3f& skin = user.skin_rgb;
  const float stripes = float(2.0 * user.stripe_width_m);  // one shirt and one stripe color per period
  std::vector<MeshVertex> mesh;
  append_head(mesh, pose, skin, detail);
  append_capsule(mesh, pose.neck_base, pose.neck_base + (pose.head_centre - pose.neck_base) * 0.6, 0.05, 0.05,
                 Eigen::Vector3d::UnitX(), body, skin, skin, 0.0f, detail);
  append_capsule(mesh, pose.pelvis, pose.neck_base, pose.shoulder_width_m / 2, pose.torso_depth_m / 2,
                 Eigen::Vector3d::UnitX(), body, user.shirt_rgb, user.shirt_stripe_rgb, stripes, detail);
  for (const ArmPose* arm : {&pose.left_arm, &pose.right_arm}) {
    append_capsule(mesh, arm->shoulder, arm->elbow, 0.045, 0.045, Eigen::Vector3d::UnitX(), body, user.shirt_rgb,
                   user.shirt_stripe_rgb, stripes, detail);
    append_forearm(mesh, *arm, skin, detail);
  }
  append_hand(mesh, pose.right_hand, user.hand_scale, skin, detail);
  append_hand(mesh, pose.left_hand, user.hand_scale, skin, detail);
  return mesh;
}

}  // namespace rt::sim
