// The generator of the hand template: tubes of elliptic (palm: rounded-rectangle) rings along
// the rest skeleton of sim::medium_adult_hand(), weighted to the bones they follow with
// smooth blends across the joints, and planar UVs into a two-sided skin atlas. The hand's
// triangles come first, the forearm's (a tube from the wrist to the elbow, as thick as the
// simulator's forearm) after them, so that a renderer can leave the forearm out.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include "hand/hand_template.h"
#include "sim/hand_model.h"
#include "sim/person_mesh.h"

namespace rt::hand {
namespace {

using Eigen::Vector3d;

double smoothstep(double edge0, double edge1, double x) {
  const double t = std::clamp((x - edge0) / (edge1 - edge0), 0.0, 1.0);
  return t * t * (3 - 2 * t);
}

// Up to four (bone, weight) pairs.
struct Influence {
  std::array<int, 4> bone{0, 0, 0, 0};
  std::array<double, 4> weight{0, 0, 0, 0};
  void add(int b, double w) {
    if (!(w > 1e-4)) return;
    for (int k = 0; k < 4; ++k)
      if (weight[k] > 0 && bone[k] == b) {
        weight[k] += w;
        return;
      }
    // Replace the smallest when full: no vertex takes more than four bones.
    int smallest = 0;
    for (int k = 1; k < 4; ++k)
      if (weight[k] < weight[smallest]) smallest = k;
    if (weight[smallest] < w) bone[smallest] = b, weight[smallest] = w;
  }
};

struct Ring {
  Vector3d centre, lateral, normal;  // lateral, normal: unit, orthogonal
  double radius_lateral, radius_normal;
  double squareness = 1.0;           // 1: ellipse; < 1: towards a rounded rectangle
  Vector3d inside = Vector3d::Zero();  // a point inside the surface near the ring: normals face away
  Influence influence;
};

// Atlas: the back of the hand and forearm in u in [0, 0.5], the palm side in [0.5, 1]; planar
// projection along z of the right hand's rest position (a left hand is mirrored, so both share
// one texture), from the elbow's cap (y = -0.285) to past the middle fingertip.
constexpr double kAtlasX0 = -0.08, kAtlasWidth = 0.21, kAtlasY0 = -0.29, kAtlasHeight = 0.485;
constexpr uint32_t kTextureSize = 512;  // about 0.4 mm of hand per texel across, 1 mm along

std::array<float, 2> atlas_uv(const Vector3d& p, bool palm_side, double mirror) {
  const double u = std::clamp((mirror * p.x() - kAtlasX0) / kAtlasWidth, 0.0, 1.0);
  const double v = std::clamp((kAtlasY0 + kAtlasHeight - p.y()) / kAtlasHeight, 0.0, 1.0);
  return {float(0.5 * u + (palm_side ? 0.5 : 0.0)), float(v)};
}

class MeshBuilder {
 public:
  explicit MeshBuilder(double mirror) : mirror_(mirror) {}

  // One tube through `rings`; each ring is split into a back half and a palm half with their
  // own vertices, so that no triangle spans the two halves of the atlas.
  void tube(const std::vector<Ring>& rings, int segments) {
    const int half = segments / 2;
    for (int side = 0; side < 2; ++side) {
      const uint32_t first = uint32_t(vertices_.size());
      for (const Ring& ring : rings)
        for (int s = 0; s <= half; ++s) {
          // side 0 (back): angles pi..2pi (sin <= 0, towards -z); side 1 (palm): 0..pi.
          const double angle = std::numbers::pi * (double(s) / half + (side == 0 ? 1.0 : 0.0));
          const double c = std::cos(angle), si = std::sin(angle);
          auto shaped = [&](double x) { return std::copysign(std::pow(std::abs(x), ring.squareness), x); };
          const Vector3d p = ring.centre + shaped(c) * ring.radius_lateral * ring.lateral +
                             shaped(si) * ring.radius_normal * ring.normal;
          add_vertex(p, side == 1, ring.influence, ring.inside);
        }
      const uint32_t stride = uint32_t(half + 1);
      for (uint32_t r = 0; r + 1 < rings.size(); ++r)
        for (uint32_t s = 0; s < uint32_t(half); ++s) {
          const uint32_t a = first + r * stride + s, b = a + 1, c = a + stride, d = c + 1;
          indices_.insert(indices_.end(), {a, b, d, a, d, c});
        }
    }
  }

  size_t index_count() const { return indices_.size(); }

  HandTemplate finish(bool is_left, const RestSkeleton& rest) {
    // Area-weighted face normals, turned away from the inside of the tube: the renderer is unlit,
    // normals serve later lighting.
    std::vector<Vector3d> normals(positions_.size(), Vector3d::Zero());
    for (size_t t = 0; t + 2 < indices_.size(); t += 3) {
      const Vector3d& a = positions_[indices_[t]];
      const Vector3d n = (positions_[indices_[t + 1]] - a).cross(positions_[indices_[t + 2]] - a);
      for (int k = 0; k < 3; ++k) normals[indices_[t + k]] += n;
    }
    HandTemplate hand;
    hand.is_left = is_left;
    hand.rest = rest;
    hand.indices = indices_;
    for (size_t i = 0; i < positions_.size(); ++i) {
      const Vector3d outwards = positions_[i] - insides_[i];
      Vector3d n = normals[i].norm() > 1e-12 ? normals[i].normalized() : outwards.normalized();
      if (n.dot(outwards) < 0) n = -n;
      if (!n.allFinite()) n = Vector3d::UnitZ();
      HandVertex& v = vertices_[i];
      for (int c = 0; c < 3; ++c) v.normal_v[c] = float(n[c]);
      hand.vertices.push_back(v);
    }
    return hand;
  }

 private:
  void add_vertex(const Vector3d& p, bool palm_side, const Influence& influence, const Vector3d& inside) {
    insides_.push_back(inside);
    HandVertex v{};
    const auto uv = atlas_uv(p, palm_side, mirror_);
    v.position_u = {float(p.x()), float(p.y()), float(p.z()), uv[0]};
    v.normal_v = {0, 0, 1, uv[1]};
    double total = 0;
    for (int k = 0; k < 4; ++k) total += influence.weight[k];
    // Weights in steps of 1/255 (the file stores them as normalised bytes), summing to exactly
    // 255/255: the largest takes the remainder.
    int largest = 0, sum = 0;
    std::array<int, 4> steps{};
    for (int k = 0; k < 4; ++k) {
      steps[size_t(k)] = int(std::lround(255.0 * influence.weight[size_t(k)] / total));
      if (influence.weight[size_t(k)] > influence.weight[size_t(largest)]) largest = k;
      sum += steps[size_t(k)];
    }
    steps[size_t(largest)] += 255 - sum;
    for (int k = 0; k < 4; ++k) {
      v.joints[size_t(k)] = float(steps[size_t(k)] > 0 ? influence.bone[size_t(k)] : 0);
      v.weights[size_t(k)] = float(steps[size_t(k)] / 255.0);
    }
    vertices_.push_back(v);
    positions_.push_back(p);
  }

  double mirror_;
  std::vector<HandVertex> vertices_;
  std::vector<Vector3d> positions_;
  std::vector<Vector3d> insides_;
  std::vector<uint32_t> indices_;
};

// Rings closing a tube end: a flattened hemisphere from `end` (whose ring it copies) outwards.
// `end` is a copy: callers pass rings.back(), which the first push_back may move.
void append_cap(std::vector<Ring>& rings, const Ring end, const Vector3d& outwards, double length, int count) {
  for (int k = 1; k <= count; ++k) {
    const double phi = std::numbers::pi / 2 * k / count;
    Ring ring = end;
    ring.centre = end.centre + outwards * (length * std::sin(phi));
    ring.radius_lateral = end.radius_lateral * std::cos(phi);
    ring.radius_normal = end.radius_normal * std::cos(phi);
    ring.inside = end.centre;
    rings.push_back(ring);
  }
}

// A digit: the chain of joints from `first_bone`'s start to the tip, with radii tapering from
// `base_radius`, starting `buried` metres inside the palm along the first bone.
std::vector<Ring> digit_rings(const HandSkeleton& hand, const RestSkeleton& rest, int digit, int first_joint,
                              double base_radius, double buried, int base_parent) {
  const auto& joints = hand.digits[digit];
  std::vector<double> arc{0.0};
  for (int j = first_joint; j < kJointsPerDigit - 1; ++j) arc.push_back(arc.back() + (joints[j + 1] - joints[j]).norm());
  const double total = arc.back();
  const Vector3d lateral = rest[kWristBone].frame.linear().col(0);
  std::vector<Ring> rings;
  auto ring_at = [&](double s) {
    // Position along the chain (s < 0: inside the palm, along the first bone).
    int segment = 0;
    while (segment + 2 < int(arc.size()) && s > arc[segment + 1]) ++segment;
    const Vector3d a = joints[first_joint + segment], b = joints[first_joint + segment + 1];
    const Vector3d along = (b - a).normalized();
    Ring ring;
    ring.centre = a + along * (s - arc[segment]);
    ring.inside = ring.centre;
    ring.lateral = (lateral - along * along.dot(lateral)).normalized();
    ring.normal = ring.lateral.cross(along);
    const double taper = 1.0 - 0.28 * std::clamp(s / total, 0.0, 1.0);
    ring.radius_lateral = base_radius * taper;
    ring.radius_normal = base_radius * taper * 0.86;
    // Weights: the bone under s, blended with its neighbour within `blend` of each joint.
    const double blend = 0.006;
    const int first_bone = digit_bone(digit, first_joint);
    Influence influence;
    double remaining = 1.0;
    // Into the palm the first bone hands over to its parent.
    const double into_palm = 1.0 - smoothstep(-blend, blend, s);
    influence.add(base_parent, into_palm);
    remaining -= into_palm;
    // Piecewise: weight of bone k is the share of [arc[k]-blend, arc[k+1]+blend] under s.
    std::array<double, 4> share{};
    double share_total = 0;
    for (size_t k = 0; k + 1 < arc.size(); ++k) {
      const double in = k == 0 ? 1.0 : smoothstep(arc[k] - blend, arc[k] + blend, s);
      const double out = k + 2 == arc.size() ? 1.0 : 1.0 - smoothstep(arc[k + 1] - blend, arc[k + 1] + blend, s);
      share[k] = in * out;
      share_total += share[k];
    }
    for (size_t k = 0; k + 1 < arc.size(); ++k)
      influence.add(first_bone + int(k), remaining * share[k] / share_total);
    ring.influence = influence;
    return ring;
  };
  std::vector<double> stations{-buried, -buried * 0.5};
  for (size_t k = 0; k + 1 < arc.size(); ++k) {
    const int steps = 4;
    for (int i = 0; i < steps; ++i) stations.push_back(arc[k] + (arc[k + 1] - arc[k]) * i / steps);
  }
  stations.push_back(total);
  for (double s : stations) rings.push_back(ring_at(s));
  const Vector3d tip_direction = (joints[kJointsPerDigit - 1] - joints[kJointsPerDigit - 2]).normalized();
  append_cap(rings, rings.back(), tip_direction, rings.back().radius_normal, 5);
  return rings;
}

}  // namespace

HandTemplate build_hand_template(bool is_left) {
  sim::HandPlacement placement;
  placement.palm = Vector3d(0, sim::palm_centre_uv().y(), 0);  // puts the wrist at the origin
  HandSkeleton hand = sim::build_hand(placement, is_left, 1.0);
  hand.elbow = hand.wrist - 0.25 * hand.direction;  // a forearm of 25 cm
  const RestSkeleton rest = rest_skeleton_from(hand);
  const double mirror = is_left ? -1.0 : 1.0;
  MeshBuilder mesh(mirror);

  // The palm: one tube from just behind the wrist (hidden inside the forearm when that is
  // drawn, capped when not) to the knuckles.
  const Vector3d lateral = rest[kWristBone].frame.linear().col(0);
  const double knuckle_y = 0.080, palm_start_y = -0.03;
  // Towards the forearm the wrist hands over to the arm bone: one weight function of y for the
  // palm and the forearm, so that where the two tubes overlap they bend alike.
  auto wrist_influence = [](double y, double metacarpal) {
    Influence influence;
    const double wrist = smoothstep(-0.04, 0.005, y);
    influence.add(kArmBone, 1.0 - wrist);
    influence.add(kWristBone, wrist * (1.0 - metacarpal));
    // Towards the knuckles the palm bends a little with the middle and ring metacarpals (one
    // weight set per ring: the palm's rings are not split per finger).
    influence.add(digit_bone(2, 0), wrist * metacarpal * 0.5);
    influence.add(digit_bone(3, 0), wrist * metacarpal * 0.5);
    return influence;
  };
  std::vector<Ring> palm;
  const int palm_rings = 16;
  for (int k = 0; k <= palm_rings; ++k) {
    const double y = palm_start_y + (knuckle_y - palm_start_y) * k / double(palm_rings);
    Ring ring;
    const double on_palm = smoothstep(-0.02, 0.03, y);
    const double centre_x = mirror * (-0.004 * smoothstep(0.0, knuckle_y, y));
    ring.centre = Vector3d(centre_x, y, 0.001 * on_palm);
    ring.inside = ring.centre;
    ring.lateral = lateral;
    ring.normal = lateral.cross(Vector3d::UnitY());
    ring.radius_lateral = 0.029 + 0.0155 * smoothstep(-0.01, 0.06, y);
    ring.radius_normal = 0.020 - 0.007 * on_palm;
    ring.squareness = 1.0 - 0.45 * on_palm;
    ring.influence = wrist_influence(y, 0.6 * smoothstep(0.035, knuckle_y, y));
    palm.push_back(ring);
  }
  append_cap(palm, palm.back(), Vector3d::UnitY(), 0.010, 4);
  std::reverse(palm.begin(), palm.end());
  append_cap(palm, palm.back(), -Vector3d::UnitY(), 0.010, 3);
  mesh.tube(palm, 28);

  // Index to pinky from 2 cm inside the palm; the thumb from its base, 1.5 cm inside.
  const double radii[kDigitCount] = {0.0105, 0.0095, 0.0095, 0.009, 0.008};
  for (int d = 1; d < kDigitCount; ++d)
    mesh.tube(digit_rings(hand, rest, d, int(DigitJoint::Mcp), radii[d], 0.02, digit_bone(d, 0)), 20);
  // The thumb's chain starts at carp == mcp; its zero-length metacarpal carries no weight.
  auto thumb = digit_rings(hand, rest, 0, int(DigitJoint::Mcp), radii[0] * 1.25, 0.015, kWristBone);
  mesh.tube(thumb, 20);
  const size_t hand_indices = mesh.index_count();

  // The forearm: round, as thick as the simulator's (so that a fitted forearm covers the true
  // one), from a cap at the elbow to 1.5 cm before the wrist, narrowing over its last 5 cm into
  // the palm tube's wrist, inside which it ends.
  const double forearm = rest[kArmBone].length_m, radius = sim::kForearmRadiusM, end_y = -0.015;
  std::vector<Ring> arm;
  const int arm_rings = 24;
  for (int k = 0; k <= arm_rings; ++k) {
    const double y = -forearm + (end_y + forearm) * k / double(arm_rings);
    const double narrowing = smoothstep(-0.07, -0.025, y);
    Ring ring;
    ring.centre = Vector3d(0, y, 0);
    ring.inside = ring.centre;
    ring.lateral = lateral;
    ring.normal = lateral.cross(Vector3d::UnitY());
    ring.radius_lateral = radius + (0.0285 - radius) * narrowing;
    ring.radius_normal = radius + (0.0195 - radius) * narrowing;
    ring.influence = wrist_influence(y, 0.0);
    arm.push_back(ring);
  }
  append_cap(arm, arm.back(), Vector3d::UnitY(), 0.008, 3);
  std::reverse(arm.begin(), arm.end());
  append_cap(arm, arm.back(), -Vector3d::UnitY(), radius, 5);
  mesh.tube(arm, 28);

  HandTemplate result = mesh.finish(is_left, rest);
  result.hand_index_count = uint32_t(hand_indices);
  result.palm_width_m = sim::palm_width_m(1.0);  // what the simulated tracker reports for this hand
  result.arm_width_m = 2 * radius;
  result.texture = build_skin_texture(kTextureSize);
  return result;
}

HostImage build_skin_texture(uint32_t size) {
  // A medium skin albedo (linear RGB) with low-frequency variation, a lighter palm with creases,
  // knuckle wrinkles and nails, painted in the atlas of atlas_uv().
  HostImage texture(size, size, PixelFormat::RGBA32F);
  const Eigen::Vector3d back(0.62, 0.43, 0.33), palm(0.70, 0.50, 0.40), nail(0.80, 0.62, 0.58), crease(0.52, 0.35, 0.27);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> phase(0.0, 6.283);
  const double p1 = phase(rng), p2 = phase(rng), p3 = phase(rng);
  // Right hand rest joints: nails lie on the back over the distal bones.
  sim::HandPlacement placement;
  placement.palm = Vector3d(0, sim::palm_centre_uv().y(), 0);
  const HandSkeleton hand = sim::build_hand(placement, false, 1.0);
  for (uint32_t py = 0; py < size; ++py)
    for (uint32_t px = 0; px < size; ++px) {
      const double u = (px + 0.5) / size, v = (py + 0.5) / size;
      const bool palm_side = u >= 0.5;
      const double x = kAtlasX0 + kAtlasWidth * (palm_side ? 2 * u - 1 : 2 * u);
      const double y = kAtlasY0 + kAtlasHeight - kAtlasHeight * v;
      Eigen::Vector3d c = palm_side ? palm : back;
      const double variation = 0.03 * std::sin(60 * x + p1) * std::sin(45 * y + p2) + 0.02 * std::sin(110 * (x + y) + p3);
      c *= 1.0 + variation;
      if (palm_side) {
        // Two palm creases across the palm.
        const double line1 = std::abs(y - (0.062 - 0.25 * x)), line2 = std::abs(y - (0.045 + 0.15 * x));
        if ((line1 < 0.0012 && x > -0.035 && x < 0.03) || (line2 < 0.0012 && x > -0.04 && x < 0.02)) c = crease;
      }
      for (int d = 0; d < kDigitCount; ++d) {
        const Eigen::Vector3d dip = hand.digits[d][int(DigitJoint::Dip)], tip = hand.digits[d][int(DigitJoint::Tip)];
        const Eigen::Vector2d axis = (tip - dip).head<2>().normalized();
        const Eigen::Vector2d rel = Eigen::Vector2d(x, y) - tip.head<2>();
        const double along = rel.dot(axis), across = std::abs(rel.x() * axis.y() - rel.y() * axis.x());
        if (!palm_side && along > -0.013 && along < 0.004 && across < 0.0065) c = nail;
        // Knuckle wrinkles over pip on the back.
        const Eigen::Vector2d at_pip = Eigen::Vector2d(x, y) - hand.digits[d][int(DigitJoint::Pip)].head<2>();
        if (!palm_side && d > 0 && std::abs(at_pip.dot(axis)) < 0.004 && at_pip.norm() < 0.008 &&
            std::fmod(std::abs(at_pip.dot(axis)) * 1000.0, 2.0) < 0.6)
          c *= 0.9;
      }
      for (int ch = 0; ch < 3; ++ch) texture.at(px, py, uint32_t(ch)) = float(std::clamp(c[ch], 0.0, 1.0));
      texture.at(px, py, 3) = 1.0f;
    }
  return texture;
}

}  // namespace rt::hand
