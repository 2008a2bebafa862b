// Touch from the hands' skin (touch/mesh_contact.h): each scene's true hands, skinned from their
// skeletons, meet on the glass with the scene's gesture, or do not meet at all; a graze passes
// close without meeting.
#include <catch2/catch.hpp>

#include <cstdio>
#include <string>
#include <vector>

#include "config/assets.h"
#include "geometry/site_frames.h"
#include "hand/hand_template.h"
#include "hand/shape_adaption.h"
#include "hand/skinning.h"
#include "sim/scene.h"
#include "support/hands.h"
#include "touch/mesh_contact.h"
#include "touch/mutual_touch.h"
#include "touch/scene_contact.h"

using namespace rt;

namespace {

sim::Scene gesture_scene(const std::string& name) { return sim::load_scene(sim::resolve_scene(name)); }

struct Closest {
  double gap_m = 1e9, max_overlap_m2 = 0, max_box_overlap_m2 = 0;
};

// How near the two right hands' skin comes on the glass over the whole scene (band `band_m`), and
// the largest overlap of their skin and of the paper's joint boxes.
Closest closest_approach(const sim::Scene& scene, double band_m) {
  const sim::MotionTrack a = sim::make_motion_track(scene, Site::A), b = sim::make_motion_track(scene, Site::B);
  MeshContactParameters mesh;
  mesh.band_m = band_m;
  Closest closest;
  for (double t = 0; t <= scene.duration_s(); t += 0.02) {
    const HandSkeleton local = a.pose_at(t).right_hand, remote = map_skeleton(Site::B, Site::A, b.pose_at(t).right_hand);
    const ContactPatch here = contact_patch(local, 1.0, mesh), there = contact_patch(remote, -1.0, mesh);
    closest.gap_m = std::min(closest.gap_m, patch_gap_m(here, there));
    const HandSkeleton l[] = {local}, r[] = {remote};
    closest.max_overlap_m2 = std::max(closest.max_overlap_m2, mesh_contact(l, r, mesh).overlap_area_m2);
    closest.max_box_overlap_m2 = std::max(closest.max_box_overlap_m2, overlap_area_m2(l, r, 0.02));
  }
  return closest;
}

}  // namespace

TEST_CASE("each scene's true hands meet with its own gesture, once, or never") {
  const std::vector<std::pair<std::string, std::vector<Gesture>>> expected = {
      // approach: A's hand stops 6 cm before the glass, so no rule sees a touch (nor the paper's).
      {"clap", {Gesture::Palm}},           {"approach", {}},  {"fist-bump", {Gesture::Fist}},
      {"finger-touch", {Gesture::Finger}}, {"miss", {}}, {"wave", {}}, {"graze", {}}};
  for (const auto& [name, gestures] : expected) {
    const std::vector<TrueContact> contacts = true_contacts(gesture_scene(name), hand_mesh_touch_parameters());
    std::vector<Gesture> got;
    for (const TrueContact& contact : contacts) got.push_back(contact.gesture);
    CAPTURE(name, got.size());
    REQUIRE(got.size() == gestures.size());
    for (size_t i = 0; i < got.size(); ++i) CHECK(gesture_name(got[i]) == std::string(gesture_name(gestures[i])));
  }
}

TEST_CASE("the detector names the gesture alike at every moment of the touch, not only at its start") {
  // A site's tick may first see a touch at any moment of it: on arrival or pressed on the glass.
  for (const auto& [name, gesture] :
       {std::pair{"clap", Gesture::Palm}, std::pair{"fist-bump", Gesture::Fist}, std::pair{"finger-touch", Gesture::Finger}}) {
    const sim::Scene scene = gesture_scene(name);
    const sim::MotionTrack a = sim::make_motion_track(scene, Site::A), b = sim::make_motion_track(scene, Site::B);
    const TouchParameters touch = hand_mesh_touch_parameters();
    int touching = 0;
    for (double t = 0; t <= scene.duration_s(); t += 0.01) {
      const HandSkeleton l[] = {a.pose_at(t).right_hand}, r[] = {map_skeleton(Site::B, Site::A, b.pose_at(t).right_hand)};
      const MeshContact contact = touch_overlap(l, r, touch);
      if (contact.overlap_area_m2 <= touch.end_area_m2) continue;
      ++touching;
      CAPTURE(name, t, contact.overlap_area_m2);
      CHECK(gesture_name(contact.gesture) == std::string(gesture_name(gesture)));
    }
    CHECK(touching > 50);  // the hold: a second at least
  }
}

TEST_CASE("a graze's palms pass within 3 cm on the glass without meeting") {
  const sim::Scene scene = gesture_scene("graze");
  const Closest truth = closest_approach(scene, kRestingSkinBandM);
  const Closest seen = closest_approach(scene, MeshContactParameters{}.band_m);
  std::printf("graze: closest skin on the glass %.1f mm (detector's band: %.1f mm); largest overlap: skin %.2f cm^2, joint "
              "boxes %.1f cm^2\n",
              truth.gap_m * 1e3, seen.gap_m * 1e3, seen.max_overlap_m2 * 1e4, seen.max_box_overlap_m2 * 1e4);
  CHECK(truth.gap_m <= 0.03);
  CHECK(truth.gap_m > 0.0);
  CHECK(seen.gap_m > 0.0);
  CHECK(seen.max_overlap_m2 == 0.0);
}

TEST_CASE("a flat palm's skin on the glass is a palm-sized patch; a hand off the glass has none") {
  MeshContactParameters mesh;
  const ContactPatch on = contact_patch(test::flat_hand(0, 0, sim::kTouchPalmHeightM), 1.0, mesh);
  // A palm and four fingers: roughly 9 cm by 18 cm, less the gaps between the fingers.
  CHECK(on.area_m2() > 60e-4);
  CHECK(on.area_m2() < 200e-4);
  CHECK(contact_patch(test::flat_hand(0, 0, 0.05), 1.0, mesh).cells.empty());
  // The other site's hand, 5 cm behind the glass: none either.
  CHECK(contact_patch(map_skeleton(Site::B, Site::A, test::flat_hand(0, 0, 0.05)), -1.0, mesh).cells.empty());
  const HandSkeleton here[] = {test::flat_hand(0, 0, sim::kTouchPalmHeightM)};
  const HandSkeleton there[] = {map_skeleton(Site::B, Site::A, test::flat_hand(0, 0, sim::kTouchPalmHeightM))};
  const MeshContact contact = mesh_contact(here, there, mesh);
  CHECK(contact.overlap_area_m2 > 30e-4);
  CHECK(contact.gesture == Gesture::Palm);
  CHECK_THROWS(check_mesh_contact_parameters({0.0, 0.004}));
}

TEST_CASE("the detector's skin, positions alone, is where the receiver's full skinning puts it, to the bit") {
  // The clap's hands at every 0.1 s: shaped to their bones and posed, with and without normals.
  const sim::Scene scene = gesture_scene("clap");
  const sim::MotionTrack track = sim::make_motion_track(scene, Site::A);
  size_t compared = 0;
  for (double t = 0; t <= scene.duration_s(); t += 0.1) {
    const HandSkeleton skeleton = track.pose_at(t).right_hand;
    const hand::HandTemplate hand = hand::load_hand_template(config::assets_dir() / "hand", skeleton.is_left);
    const hand::BoneScales scales = hand::bone_scales(skeleton, hand.rest, {hand.palm_width_m, hand.arm_width_m});
    REQUIRE(scales.ok());
    const hand::RestSkeleton rest = hand::adapted_rest_skeleton(hand.rest, scales);
    const auto full = hand::adapt_rest_mesh(hand.vertices, hand.rest, rest, scales);
    const auto positions = hand::adapt_rest_positions(hand.vertices, hand.rest, rest, scales);
    REQUIRE(full.size() == positions.size());
    for (size_t i = 0; i < full.size(); ++i) REQUIRE(full[i].position_u == positions[i].position_u);
    const hand::BonePose pose = hand::pose_bones(skeleton, rest);
    REQUIRE(pose.ok());
    const auto matrices = hand::skinning_matrices(pose.frames, rest);
    const auto skinned = hand::skin_vertices(full, matrices);
    const auto skinned_positions = hand::skin_positions(positions, matrices);
    REQUIRE(skinned.size() == skinned_positions.size());
    for (size_t i = 0; i < skinned.size(); ++i) REQUIRE(skinned[i].position_u == skinned_positions[i]);
    ++compared;
  }
  CHECK(compared > 20);
}

TEST_CASE("a patch cache skins each hand once and gives the patches and contacts skinning gives") {
  const sim::Scene scene = gesture_scene("clap");
  const sim::MotionTrack a = sim::make_motion_track(scene, Site::A), b = sim::make_motion_track(scene, Site::B);
  MeshContactParameters mesh;
  ContactPatchCache cache;
  size_t compared = 0;
  for (double t = 2.3; t <= 2.8; t += 0.02) {
    const HandSkeleton local[] = {a.pose_at(t).right_hand};
    const HandSkeleton remote[] = {map_skeleton(Site::B, Site::A, b.pose_at(t).right_hand)};
    // Each tick twice, as a tracker frame standing for two ticks: the second is all hits.
    for (int again = 0; again < 2; ++again) {
      const MeshContact cached = mesh_contact(local, remote, mesh, &cache), fresh = mesh_contact(local, remote, mesh);
      CHECK(cached.overlap_area_m2 == fresh.overlap_area_m2);
      CHECK(cached.gesture == fresh.gesture);
    }
    const ContactPatch& patch = cache.patch(local[0], 1.0, mesh);
    CHECK(patch.cells == contact_patch(local[0], 1.0, mesh).cells);
    ++compared;
  }
  REQUIRE(compared > 20);
  // At most the two new hands of each tick skinned (fewer where a hand holds still).
  CHECK(cache.misses() <= 2 * compared);
  CHECK(cache.hits() + cache.misses() == 5 * compared);
  // A joint moved by a hair, the other side of the glass, another band: each skinned anew.
  const HandSkeleton hand = a.pose_at(2.6).right_hand;
  HandSkeleton moved = hand;
  moved.digits[2][3].z() += 1e-9;
  (void)cache.patch(hand, 1.0, mesh);
  const uint64_t misses = cache.misses();
  (void)cache.patch(moved, 1.0, mesh);
  (void)cache.patch(hand, -1.0, mesh);
  (void)cache.patch(hand, 1.0, {0.02, 0.004});
  CHECK(cache.misses() == misses + 3);
  (void)cache.patch(hand, 1.0, mesh);
  CHECK(cache.misses() == misses + 3);
}

TEST_CASE("figures: skin on the glass per scene", "[.figures]") {
  for (const char* name : {"clap", "approach", "fist-bump", "finger-touch", "graze", "miss"}) {
    const sim::Scene scene = gesture_scene(name);
    for (const double band : {kRestingSkinBandM, MeshContactParameters{}.band_m}) {
      const Closest c = closest_approach(scene, band);
      std::printf("%-13s band %4.1f mm: closest skin %5.1f mm, largest skin overlap %6.2f cm^2, joint boxes %6.1f cm^2\n",
                  name, band * 1e3, c.gap_m * 1e3, c.max_overlap_m2 * 1e4, c.max_box_overlap_m2 * 1e4);
    }
    for (const TrueContact& contact : true_contacts(scene, hand_mesh_touch_parameters()))
      std::printf("%-13s true contact at %.3f s, %s\n", name, contact.t_s, gesture_name(contact.gesture));
  }
}

TEST_CASE("figures: nearest skin", "[.figures]") {
  for (const char* name : {"clap", "fist-bump", "finger-touch", "graze"}) {
    const sim::Scene scene = gesture_scene(name);
    const sim::MotionTrack a = sim::make_motion_track(scene, Site::A), b = sim::make_motion_track(scene, Site::B);
    const HandSkeleton ha = a.pose_at(2.9).right_hand, hb = map_skeleton(Site::B, Site::A, b.pose_at(2.9).right_hand);
    for (const auto& [hand, side] : {std::pair{ha, 1.0}, std::pair{hb, -1.0}}) {
      double lo = 0.0, hi = 0.04;
      for (int i = 0; i < 14; ++i) {
        const double mid = 0.5 * (lo + hi);
        (contact_patch(hand, side, {mid, 0.004}).cells.empty() ? lo : hi) = mid;
      }
      double nearest_joint = 1e9;
      for (const auto& j : hand.hand_joints()) nearest_joint = std::min(nearest_joint, side * j.z());
      std::printf("%-13s side %+.0f: nearest skin %.2f mm, nearest joint %.2f mm\n", name, side, hi * 1e3, nearest_joint * 1e3);
    }
  }
}
