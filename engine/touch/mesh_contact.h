#pragma once
// Mutual touch from the hands' skin rather than from their joints: each hand's template mesh is
// skinned on the CPU from its skeleton (hand/skinning.h, with the shape adaption the receiver
// draws it with), the skin within a band of the glass (or pressed through it) is projected onto
// the glass plane as a patch of small cells, and the two sides' patches overlap where the hands
// meet through the glass. The overlap and the hands' shape name the touch: only fingers in it
// (a fingertip touch), a hand with its fingers closed (a fist bump, knuckles forward), or else
// the palm (a clap, a high five). The paper's joint boxes (mutual_touch.h) see a fist bump or
// two fingertips as too small a touch (under its 50 cm^2).
#include <cstdint>
#include <deque>
#include <span>
#include <unordered_map>

#include "tracking/hand_skeleton.h"
#include "touch/gesture.h"

namespace rt {

struct MeshContactParameters {
  // Skin this close to the glass touches it: a tracker's skeleton and the template's thickness
  // are off by a few millimetres, and a hand resting on the glass has its skin pressed flat.
  double band_m = 0.01;
  double cell_m = 0.004;  // the patches' grid on the glass plane
};

// Throws with the reason unless the parameters make sense.
void check_mesh_contact_parameters(const MeshContactParameters& parameters);

enum class HandPart : uint8_t { Palm, Knuckles, Finger };

// A closed hand bends its fingers at the knuckles by about 70 degrees, an open one by under 25.
inline constexpr double kCurledKnuckleRad = 0.785;

// One hand's skin on the glass: the cells of the glass plane it covers, each with the part of
// the hand there.
struct ContactPatch {
  double cell_m = 0.004;
  std::unordered_map<int64_t, HandPart> cells;
  // The four fingers bent at their knuckles by more than kCurledKnuckleRad on average: a fist
  // (or a pointing hand, whose other fingers are closed).
  bool fingers_curled = false;
  double area_m2() const { return double(cells.size()) * cell_m * cell_m; }
};

// `side` is +1 for a hand in front of the glass (this site's) and -1 for one behind it (the other
// site's, mapped into this frame): skin on the far side of the glass counts as pressed onto it.
// An empty patch where the skeleton cannot be posed.
ContactPatch contact_patch(const HandSkeleton& hand, double side, const MeshContactParameters& parameters);

// The patches of the last few hands skinned. A tracker frame stands for several of the detector's
// ticks (more where a scene plays slowly), and the same skeleton gives the same patch, so a
// detector that keeps one skins each skeleton once. Hands are the same when every field the
// skinning reads is the same to the bit (their capture times may differ).
class ContactPatchCache {
 public:
  const ContactPatch& patch(const HandSkeleton& hand, double side, const MeshContactParameters& parameters);
  uint64_t hits() const { return hits_; }
  uint64_t misses() const { return misses_; }

 private:
  struct Entry {
    HandSkeleton hand;
    double side = 1.0;
    MeshContactParameters parameters;
    ContactPatch patch;
  };
  static constexpr size_t kEntries = 8;  // two sides' hands, as seen and as predicted at the glass
  std::deque<Entry> entries_;  // newest first
  uint64_t hits_ = 0, misses_ = 0;
};

struct MeshContact {
  double overlap_area_m2 = 0.0;    // of the pair of hands that overlap most
  Gesture gesture = Gesture::Palm;  // what that pair's overlap is made of
};

// The largest overlap between a local hand's patch and a remote hand's (hands in the local site
// frame), and its gesture: each hand's own (hand_gesture), the more pointed of the two where they
// differ (a fingertip on a palm is a fingertip touch, a fist into a palm a fist bump).
// `cache`, where given, keeps the patches for the next call.
MeshContact mesh_contact(std::span<const HandSkeleton> local_hands, std::span<const HandSkeleton> remote_hands,
                         const MeshContactParameters& parameters, ContactPatchCache* cache = nullptr);

// The gesture a hand makes with the cells of its patch that `other` covers too: finger where
// fingers' second and last bones make three quarters of them (a fingertip), else fist where its
// fingers are curled, else palm. Which bone lies nearest the glass cannot tell a fist from a
// palm: a fist's knuckles are the heads of the bones in the palm.
Gesture hand_gesture(const ContactPatch& patch, const ContactPatch& other);

// The smallest distance on the glass between two patches' cells (m; infinite if either is empty):
// how near two hands came to meeting.
double patch_gap_m(const ContactPatch& a, const ContactPatch& b);

}  // namespace rt
