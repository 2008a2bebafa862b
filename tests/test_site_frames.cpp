// The shared virtual space: site B maps to the global frame (site A's) by a 180-degree turn
// about +y, so both screens coincide and a point on the glass is the same spot for both users.
#include <catch2/catch.hpp>

#include "geometry/site_frames.h"
#include "support/hands.h"

using namespace rt;

TEST_CASE("B to global is (x, y, z) -> (-x, y, -z); A is the global frame", "[site_frames]") {
  const Eigen::Vector3d p(0.3, 0.2, 0.7);
  CHECK((global_from_site(Site::A) * p - p).norm() < 1e-12);
  CHECK((global_from_site(Site::B) * p - Eigen::Vector3d(-0.3, 0.2, -0.7)).norm() < 1e-12);
  CHECK((map_point(Site::B, Site::A, p) - Eigen::Vector3d(-0.3, 0.2, -0.7)).norm() < 1e-12);
  CHECK((map_point(Site::A, Site::B, p) - Eigen::Vector3d(-0.3, 0.2, -0.7)).norm() < 1e-12);
  CHECK(global_from_site(Site::B).linear().determinant() == Approx(1.0));  // a rotation, not a mirror
}

TEST_CASE("mapping there and back is the identity", "[site_frames]") {
  for (Site from : {Site::A, Site::B})
    for (Site to : {Site::A, Site::B}) {
      const Eigen::Isometry3d round_trip = site_from_site(from, to) * site_from_site(to, from);
      CHECK((round_trip.matrix() - Eigen::Matrix4d::Identity()).norm() < 1e-12);
    }
}

TEST_CASE("the remote viewer's eye lands behind our screen, facing us", "[site_frames]") {
  // Viewer at site B sits 0.7 m in front of their screen, slightly to their left.
  const Eigen::Vector3d eye_b(-0.1, 0.05, 0.7);
  const Eigen::Vector3d eye_in_a = map_point(Site::B, Site::A, eye_b);
  CHECK(eye_in_a.z() == Approx(-0.7));  // behind our glass
  CHECK(eye_in_a.x() == Approx(0.1));   // their left is our right
}

TEST_CASE("a remote skeleton maps joints and directions; the glass point stays put", "[site_frames]") {
  const HandSkeleton hand = test::flat_hand(-0.2, 0.1, 0.0, 42);
  const HandSkeleton mapped = map_skeleton(Site::B, Site::A, hand);
  CHECK(mapped.timestamp_us == 42);
  CHECK((mapped.palm - Eigen::Vector3d(0.2, 0.1, 0.0)).norm() < 1e-12);
  CHECK((mapped.palm_normal - Eigen::Vector3d(0, 0, 1)).norm() < 1e-12);  // now faces us, through the glass
  CHECK((mapped.joint(Digit::Index, DigitJoint::Tip) - map_point(Site::B, Site::A, hand.joint(Digit::Index, DigitJoint::Tip)))
            .norm() < 1e-12);
}

TEST_CASE("screen rectangle and distance to it", "[site_frames]") {
  const Screen screen;
  CHECK(screen.contains({0.7195, 0.4045}));
  CHECK_FALSE(screen.contains({0.72, 0.0}));
  CHECK(distance_to_screen({0.1, 0.2, -0.03}) == Approx(0.03));
}
