// The target view: the remote eye's off-axis view through the screen lands one-to-one on the
// remote screen's pixels.
#include <catch2/catch.hpp>

#include "geometry/target_view.h"

using namespace rt;

TEST_CASE("screen corners land on the image corners, whatever the eye position", "[target_view]") {
  const Screen screen;
  for (const Eigen::Vector3d& eye_b : {Eigen::Vector3d(0, 0.1, 0.7), Eigen::Vector3d(-0.3, 0.25, 0.55),
                                       Eigen::Vector3d(0.5, -0.2, 1.2)}) {
    const Eigen::Vector3d eye = map_point(Site::B, Site::A, eye_b);  // B's viewer, in A's frame
    const Camera camera = target_view_camera(eye, screen, 1280, 720);
    // B's top-left screen corner, as B sees it, is A's (+W/2, +H/2).
    const auto top_left = camera.project({screen.width_m / 2, screen.height_m / 2, 0});
    const auto bottom_right = camera.project({-screen.width_m / 2, -screen.height_m / 2, 0});
    REQUIRE(top_left);
    REQUIRE(bottom_right);
    CHECK(top_left->x() == Approx(-0.5).margin(1e-9));
    CHECK(top_left->y() == Approx(-0.5).margin(1e-9));
    CHECK(bottom_right->x() == Approx(1279.5).margin(1e-9));
    CHECK(bottom_right->y() == Approx(719.5).margin(1e-9));
    // A point on the glass is seen where B's screen shows it: B's pixel of B's (x, y).
    const Eigen::Vector3d on_glass_b(0.2, -0.1, 0.0);
    const auto pixel = camera.project(map_point(Site::B, Site::A, on_glass_b));
    REQUIRE(pixel);
    CHECK(pixel->x() + 0.5 == Approx((on_glass_b.x() + screen.width_m / 2) / screen.width_m * 1280));
    CHECK(pixel->y() + 0.5 == Approx((screen.height_m / 2 - on_glass_b.y()) / screen.height_m * 720));
  }
}

TEST_CASE("an eye on or behind the screen plane is an error", "[target_view]") {
  const Screen screen;
  CHECK_THROWS_WITH(target_view_camera({0, 0, 0}, screen, 64, 36), Catch::Contains("in front of their own screen"));
  CHECK_THROWS_WITH(target_view_camera({0, 0, 0.3}, screen, 64, 36), Catch::Contains("z = 0.3"));
  CHECK_THROWS_WITH(target_view_camera({0, std::nan(""), -0.7}, screen, 64, 36), Catch::Contains("not finite"));
  CHECK_THROWS(target_view_camera({0, 0, -0.7}, screen, 0, 36));
}

TEST_CASE("the user's face is in view, the right way up", "[target_view]") {
  const Camera camera = target_view_camera({0, 0.1, -0.7}, Screen{}, 640, 360);
  const auto chin = camera.project({0.0, 0.0, 0.7});
  const auto forehead = camera.project({0.0, 0.2, 0.7});
  const auto users_right_hand = camera.project({0.3, 0.0, 0.4});  // at our user's +x
  REQUIRE(chin);
  REQUIRE(forehead);
  REQUIRE(users_right_hand);
  CHECK(forehead->y() < chin->y());                 // up is up
  CHECK(users_right_hand->x() < chin->x());         // the remote viewer sees our user's right on their left
}
