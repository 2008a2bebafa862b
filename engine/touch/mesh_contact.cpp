#include "touch/mesh_contact.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <mutex>
#include <stdexcept>
#include <vector>

#include "config/assets.h"
#include "hand/hand_template.h"
#include "hand/shape_adaption.h"
#include "hand/skinning.h"

namespace rt {
namespace {

// The fingers' share of a hand's overlap from which it is a fingertip touch.
constexpr double kFingertipShare = 0.75;

// The mean bend of the four fingers at their knuckles (radians): between each finger's first
// bone and the bone in the palm it sits on.
double knuckle_bend_rad(const HandSkeleton& hand) {
  double sum = 0;
  int count = 0;
  for (const Digit digit : {Digit::Index, Digit::Middle, Digit::Ring, Digit::Pinky}) {
    const Eigen::Vector3d palm_bone = hand.joint(digit, DigitJoint::Mcp) - hand.joint(digit, DigitJoint::Carp);
    const Eigen::Vector3d first_bone = hand.joint(digit, DigitJoint::Pip) - hand.joint(digit, DigitJoint::Mcp);
    if (!palm_bone.allFinite() || !first_bone.allFinite() || palm_bone.norm() < 1e-6 || first_bone.norm() < 1e-6) continue;
    sum += std::acos(std::clamp(palm_bone.normalized().dot(first_bone.normalized()), -1.0, 1.0));
    ++count;
  }
  return count ? sum / count : 0.0;
}

struct ContactMesh {
  hand::HandTemplate hand;
  std::vector<HandPart> part_of_vertex;
};

HandPart part_of_bone(int bone) {
  if (bone < 2) return HandPart::Palm;  // the arm, the palm
  const int digit = (bone - 2) / hand::kBonesPerDigit, along = (bone - 2) % hand::kBonesPerDigit;
  if (along == 0) return HandPart::Palm;  // a metacarpal lies in the palm
  if (digit == int(Digit::Thumb)) return along == 1 ? HandPart::Palm : HandPart::Finger;  // its ball is palm
  return along == 1 ? HandPart::Knuckles : HandPart::Finger;
}

ContactMesh load_contact_mesh(bool is_left) {
  ContactMesh mesh{hand::load_hand_template(config::assets_dir() / "hand", is_left), {}};
  for (const hand::HandVertex& v : mesh.hand.vertices) {
    int dominant = 0;
    for (int k = 1; k < 4; ++k)
      if (v.weights[k] > v.weights[dominant]) dominant = k;
    mesh.part_of_vertex.push_back(part_of_bone(std::clamp(int(v.joints[dominant] + 0.5f), 0, hand::kBoneCount - 1)));
  }
  return mesh;
}

// Loaded once, on first use, for every detector in the process.
const ContactMesh& contact_mesh(bool is_left) {
  static std::once_flag once;
  static ContactMesh left, right;
  std::call_once(once, [] {
    left = load_contact_mesh(true);
    right = load_contact_mesh(false);
  });
  return is_left ? left : right;
}

int64_t cell_key(int64_t ix, int64_t iy) { return (ix << 32) ^ (iy & 0xffffffffLL); }

// Where the hand's skin is, in the skeleton's frame, shaped to its bones as the receiver draws it
// (the receiver's positions; the normals, which the detector never reads, are not computed).
std::vector<std::array<float, 4>> skin(const HandSkeleton& skeleton, const hand::HandTemplate& hand) {
  const hand::BoneScales scales = hand::bone_scales(skeleton, hand.rest, {hand.palm_width_m, hand.arm_width_m});
  hand::RestSkeleton rest = hand.rest;
  std::vector<hand::HandVertex> adapted;
  std::span<const hand::HandVertex> vertices = hand.vertices;
  if (scales.ok()) {
    rest = hand::adapted_rest_skeleton(hand.rest, scales);
    adapted = hand::adapt_rest_positions(hand.vertices, hand.rest, rest, scales);
    vertices = adapted;
  }
  const hand::BonePose pose = hand::pose_bones(skeleton, rest);
  if (!pose.ok()) return {};
  return hand::skin_positions(vertices, hand::skinning_matrices(pose.frames, rest));
}

void rasterize(ContactPatch& patch, const Eigen::Vector2d (&p)[3], HandPart part) {
  const double cell = patch.cell_m;
  const Eigen::Vector2d lo = p[0].cwiseMin(p[1]).cwiseMin(p[2]), hi = p[0].cwiseMax(p[1]).cwiseMax(p[2]);
  const double twice_area = (p[1] - p[0]).x() * (p[2] - p[0]).y() - (p[1] - p[0]).y() * (p[2] - p[0]).x();
  for (const Eigen::Vector2d& corner : p)
    patch.cells.try_emplace(cell_key(int64_t(std::floor(corner.x() / cell)), int64_t(std::floor(corner.y() / cell))), part);
  if (std::abs(twice_area) < 1e-12) return;
  for (int64_t ix = int64_t(std::floor(lo.x() / cell)); ix <= int64_t(std::floor(hi.x() / cell)); ++ix)
    for (int64_t iy = int64_t(std::floor(lo.y() / cell)); iy <= int64_t(std::floor(hi.y() / cell)); ++iy) {
      const Eigen::Vector2d c((double(ix) + 0.5) * cell, (double(iy) + 0.5) * cell);
      bool inside = true;
      for (int e = 0; e < 3 && inside; ++e) {
        const Eigen::Vector2d a = p[e], b = p[(e + 1) % 3];
        const double edge = (b - a).x() * (c - a).y() - (b - a).y() * (c - a).x();
        inside = edge * twice_area >= 0;
      }
      if (inside) patch.cells.try_emplace(cell_key(ix, iy), part);
    }
}

template <typename T>
bool same_bits(const T& a, const T& b) {
  return std::memcmp(&a, &b, sizeof(T)) == 0;
}

// Every field contact_patch reads, compared by its bits (a NaN elbow equals itself).
bool same_hand_shape(const HandSkeleton& a, const HandSkeleton& b) {
  return a.is_left == b.is_left && same_bits(a.wrist, b.wrist) && same_bits(a.palm, b.palm) &&
         same_bits(a.elbow, b.elbow) && same_bits(a.palm_normal, b.palm_normal) && same_bits(a.direction, b.direction) &&
         same_bits(a.digits, b.digits) && same_bits(a.palm_width_m, b.palm_width_m) &&
         same_bits(a.arm_width_m, b.arm_width_m);
}

int severity(Gesture gesture) { return gesture == Gesture::Finger ? 2 : gesture == Gesture::Fist ? 1 : 0; }

}  // namespace

void check_mesh_contact_parameters(const MeshContactParameters& p) {
  if (!(p.band_m > 0) || !(p.band_m < 0.05)) throw std::invalid_argument("mesh contact: the band must be in (0, 5 cm)");
  if (!(p.cell_m >= 0.001) || !(p.cell_m <= 0.02))
    throw std::invalid_argument("mesh contact: the cell size must be in [1 mm, 2 cm]");
}

ContactPatch contact_patch(const HandSkeleton& skeleton, double side, const MeshContactParameters& parameters) {
  ContactPatch patch;
  patch.cell_m = parameters.cell_m;
  // No skin lies further from a joint than a finger's or the palm's thickness: a hand whose
  // joints are all further out than that is not skinned (most ticks, most hands).
  constexpr double kSkinBeyondJointM = 0.03;
  double nearest = std::numeric_limits<double>::infinity();
  for (const Eigen::Vector3d& joint : skeleton.hand_joints())
    if (joint.allFinite()) nearest = std::min(nearest, side * joint.z());
  if (!(nearest <= parameters.band_m + kSkinBeyondJointM)) return patch;
  patch.fingers_curled = knuckle_bend_rad(skeleton) > kCurledKnuckleRad;
  const ContactMesh& mesh = contact_mesh(skeleton.is_left);
  const std::vector<std::array<float, 4>> skinned = skin(skeleton, mesh.hand);
  if (skinned.empty()) return patch;
  auto touching = [&](uint32_t i) {
    const float z = skinned[i][2];
    return std::isfinite(z) && side * double(z) <= parameters.band_m;
  };
  const std::vector<uint32_t>& indices = mesh.hand.indices;
  for (uint32_t t = 0; t + 2 < mesh.hand.hand_index_count; t += 3) {
    const uint32_t i[3] = {indices[t], indices[t + 1], indices[t + 2]};
    if (!touching(i[0]) || !touching(i[1]) || !touching(i[2])) continue;
    Eigen::Vector2d p[3];
    uint32_t nearest = i[0];
    for (int k = 0; k < 3; ++k) {
      p[k] = {skinned[i[k]][0], skinned[i[k]][1]};
      if (side * skinned[i[k]][2] < side * skinned[nearest][2]) nearest = i[k];
    }
    rasterize(patch, p, mesh.part_of_vertex[nearest]);
  }
  return patch;
}

const ContactPatch& ContactPatchCache::patch(const HandSkeleton& hand, double side,
                                             const MeshContactParameters& parameters) {
  for (auto entry = entries_.begin(); entry != entries_.end(); ++entry)
    if (entry->side == side && entry->parameters.band_m == parameters.band_m &&
        entry->parameters.cell_m == parameters.cell_m && same_hand_shape(entry->hand, hand)) {
      ++hits_;
      if (entry != entries_.begin()) {
        Entry found = std::move(*entry);
        entries_.erase(entry);
        entries_.push_front(std::move(found));
      }
      return entries_.front().patch;
    }
  ++misses_;
  entries_.push_front({hand, side, parameters, contact_patch(hand, side, parameters)});
  if (entries_.size() > kEntries) entries_.pop_back();
  return entries_.front().patch;
}

Gesture hand_gesture(const ContactPatch& patch, const ContactPatch& other) {
  double counts[3] = {0, 0, 0}, total = 0;
  for (const auto& [key, part] : patch.cells)
    if (other.cells.count(key)) {
      counts[int(part)] += 1;
      total += 1;
    }
  if (total == 0) return Gesture::Palm;
  if (counts[int(HandPart::Finger)] >= kFingertipShare * total) return Gesture::Finger;
  return patch.fingers_curled ? Gesture::Fist : Gesture::Palm;
}

MeshContact mesh_contact(std::span<const HandSkeleton> local_hands, std::span<const HandSkeleton> remote_hands,
                         const MeshContactParameters& parameters, ContactPatchCache* cache) {
  MeshContact best;
  if (local_hands.empty() || remote_hands.empty()) return best;
  auto patch_of = [&](const HandSkeleton& hand, double side) {
    return cache ? cache->patch(hand, side, parameters) : contact_patch(hand, side, parameters);
  };
  std::vector<ContactPatch> remote;
  for (const HandSkeleton& hand : remote_hands) remote.push_back(patch_of(hand, -1.0));
  for (const HandSkeleton& hand : local_hands) {
    const ContactPatch local = patch_of(hand, 1.0);
    if (local.cells.empty()) continue;
    for (const ContactPatch& other : remote) {
      size_t shared = 0;
      for (const auto& [key, part] : local.cells) shared += other.cells.count(key);
      const double area = double(shared) * parameters.cell_m * parameters.cell_m;
      if (area <= best.overlap_area_m2) continue;
      best.overlap_area_m2 = area;
      const Gesture here = hand_gesture(local, other), there = hand_gesture(other, local);
      best.gesture = severity(here) >= severity(there) ? here : there;
    }
  }
  return best;
}

double patch_gap_m(const ContactPatch& a, const ContactPatch& b) {
  if (a.cells.empty() || b.cells.empty()) return std::numeric_limits<double>::infinity();
  auto centre = [](int64_t key, double cell) {
    const int64_t ix = key >> 32, iy = int64_t(int32_t(uint32_t(key & 0xffffffffLL)));
    return Eigen::Vector2d((double(ix) + 0.5) * cell, (double(iy) + 0.5) * cell);
  };
  double best = std::numeric_limits<double>::infinity();
  for (const auto& [ka, pa] : a.cells)
    for (const auto& [kb, pb] : b.cells) best = std::min(best, (centre(ka, a.cell_m) - centre(kb, b.cell_m)).norm());
  // Cell centres: two touching cells are one cell apart and leave no gap.
  return std::max(0.0, best - a.cell_m);
}

}  // namespace rt
