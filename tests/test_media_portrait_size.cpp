// The portrait's size under a narrow path (media/portrait_size_rule.h): its steps down while loss
// holds the rate at its floor, back up once the loss ends, no flapping on noise or on a path that
// loses again when given more; and the nearest-code resampling the depth/alpha track uses on both
// sides (media/portrait_size_rule.h), which must never invent a code.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <stdexcept>
#include <vector>

#include "media/portrait_size_rule.h"

using rt::media::PortraitSizeRule;
using rt::media::PortraitSizeRuleOptions;

namespace {

// Feeds one decision a second from `start_s` for `seconds`, at `kbps` with `loss` (a function of
// the second's index); returns the step after each.
template <typename Loss>
std::vector<int> feed_size_rule(PortraitSizeRule& rule, double& now_s, int seconds, int kbps, Loss loss) {
  std::vector<int> steps;
  for (int i = 0; i < seconds; ++i, now_s += 1.0) steps.push_back(rule.on_decision(now_s, kbps, loss(i), 0.01));
  return steps;
}

}  // namespace

TEST_CASE("the portrait's size steps down at the floor under loss and back up when it ends", "[media][size]") {
  PortraitSizeRuleOptions options;  // floor 300, near it up to 345; down after 3 s, up after 4 s
  PortraitSizeRule rule(options);
  double now = 0;
  // Loss above the floor: the bitrate rule still has room, the size stays.
  auto steps = feed_size_rule(rule, now, 10, 600, [](int) { return 0.15; });
  CHECK(steps.back() == 0);
  // At the floor, losing 15 %: one step once a whole period (3 s back to a decision at or before
  // its start) has been seen, the next a whole period after that, none past the last.
  steps = feed_size_rule(rule, now, 12, 300, [](int) { return 0.15; });
  CHECK(steps == std::vector<int>{0, 0, 0, 1, 1, 1, 1, 2, 2, 2, 2, 2});
  CHECK(rule.steps_down() == 2);
  // The loss ends, the rate still at the floor: back up once more than half of a period (4 s) is
  // clean (the third clean second: its period still holds two lossy ones), the next step a whole
  // period of clean decisions after that, not both at once.
  steps = feed_size_rule(rule, now, 12, 300, [](int) { return 0.0; });
  CHECK(steps == std::vector<int>{2, 2, 1, 1, 1, 1, 1, 0, 0, 0, 0, 0});
  CHECK(rule.steps_up() == 2);
}

TEST_CASE("the portrait's size ignores single lossy seconds and holds between its thresholds", "[media][size]") {
  PortraitSizeRule rule{PortraitSizeRuleOptions{}};
  double now = 0;
  // On a loaded machine a clean path draws the odd NACK: one second in three reads 10 % lost. The
  // median stays clean: nothing steps down.
  auto steps = feed_size_rule(rule, now, 20, 300, [](int i) { return i % 3 == 0 ? 0.10 : 0.0; });
  CHECK(steps.back() == 0);
  CHECK(rule.steps_down() == 0);
  // Loss between the two thresholds (3 %): not enough to step down ...
  steps = feed_size_rule(rule, now, 20, 300, [](int) { return 0.03; });
  CHECK(rule.steps_down() == 0);
  // ... nor, once down, little enough to step up.
  while (rule.step() == 0) rule.on_decision(now += 1, 300, 0.2, 0.01);
  steps = feed_size_rule(rule, now, 20, 300, [](int) { return 0.03; });
  CHECK(steps.back() == 1);
  CHECK(rule.steps_up() == 0);
  // A long round trip counts as loss, whatever the reports say.
  for (int i = 0; i < 6; ++i, now += 1) rule.on_decision(now, 300, 0.0, 0.9);
  CHECK(rule.step() == 2);
  // Reports that say nothing change nothing.
  CHECK(rule.on_decision(now, 300, std::numeric_limits<double>::quiet_NaN(), 0.01) == 2);
  CHECK(rule.on_decision(now, 300, 1.5, 0.01) == 2);
}

TEST_CASE("the portrait's size waits longer to step up on a path that loses again", "[media][size]") {
  PortraitSizeRule rule{PortraitSizeRuleOptions{}};
  double now = 0;
  while (rule.step() == 0) rule.on_decision(now += 1, 300, 0.2, 0.01);
  // A path that loses whenever the size comes back: each step down soon after a step up doubles
  // the wait before the next step up, so the size changes less and less often.
  std::vector<double> up_waits;
  for (int cycle = 0; cycle < 4; ++cycle) {
    const double start = now;
    while (rule.step() == 1) rule.on_decision(now += 1, 300, 0.0, 0.01);
    up_waits.push_back(now - start);
    while (rule.step() == 0) rule.on_decision(now += 1, 300, 0.2, 0.01);
  }
  CHECK(up_waits[0] == 5);  // 4 s, and the first decision after the change opens the period
  CHECK(up_waits[1] == 9);
  CHECK(up_waits[2] == 17);
  CHECK(up_waits[3] == 33);
  CHECK(rule.up_after_s() == 32);  // 8x at most
  // Clean at the call's size for the flap window: the wait is back to its start.
  while (rule.step() == 1) rule.on_decision(now += 1, 300, 0.0, 0.01);
  feed_size_rule(rule, now, 31, 300, [](int) { return 0.0; });
  CHECK(rule.up_after_s() == 4);
}

TEST_CASE("the portrait's sizes are even and the size rule refuses bad options", "[media][size]") {
  using rt::media::portrait_size_at_step;
  CHECK(portrait_size_at_step(1280, 720, 0) == std::pair<uint32_t, uint32_t>{1280, 720});
  CHECK(portrait_size_at_step(1280, 720, 1) == std::pair<uint32_t, uint32_t>{960, 540});
  CHECK(portrait_size_at_step(1280, 720, 2) == std::pair<uint32_t, uint32_t>{640, 360});
  CHECK(portrait_size_at_step(640, 360, 1) == std::pair<uint32_t, uint32_t>{480, 270});
  CHECK(portrait_size_at_step(96, 54, 1) == std::pair<uint32_t, uint32_t>{72, 40});  // 40.5 to an even 40
  CHECK(portrait_size_at_step(2, 2, 2) == std::pair<uint32_t, uint32_t>{2, 2});
  CHECK_THROWS_AS(portrait_size_at_step(1280, 720, 3), std::invalid_argument);
  CHECK_THROWS_AS(portrait_size_at_step(1280, 720, -1), std::invalid_argument);
  const auto refused = [](auto change) {
    PortraitSizeRuleOptions o;
    change(o);
    CHECK_FALSE(rt::media::check_portrait_size_rule(o).empty());
    CHECK_THROWS_AS(PortraitSizeRule(o), std::invalid_argument);
  };
  refused([](PortraitSizeRuleOptions& o) { o.floor_kbps = 0; });
  refused([](PortraitSizeRuleOptions& o) { o.near_floor = 0.9; });
  refused([](PortraitSizeRuleOptions& o) { o.loss_clear = o.loss_pressed; });  // no hysteresis
  refused([](PortraitSizeRuleOptions& o) { o.loss_pressed = 1.0; });
  refused([](PortraitSizeRuleOptions& o) { o.down_after_s = 0; });
  refused([](PortraitSizeRuleOptions& o) { o.up_after_s = std::numeric_limits<double>::quiet_NaN(); });
  refused([](PortraitSizeRuleOptions& o) { o.round_trip_high_s = -1; });
  CHECK(rt::media::check_portrait_size_rule(PortraitSizeRuleOptions{}).empty());
}

TEST_CASE("depth and alpha codes resample to the nearest code and never a new one", "[media][size]") {
  using rt::media::resample_codes_nearest;
  // A user (depth codes 300..400) on an empty background (0), with a hard silhouette.
  constexpr uint32_t w = 64, h = 36;
  std::vector<uint16_t> codes(w * h, 0);
  for (uint32_t y = 8; y < 30; ++y)
    for (uint32_t x = 20; x < 44; ++x) codes[y * w + x] = uint16_t(300 + (x + y) % 101);
  const std::set<uint16_t> sent(codes.begin(), codes.end());
  const std::vector<uint16_t> down = resample_codes_nearest(codes, w, h, 48, 28);
  const std::vector<uint16_t> up = resample_codes_nearest(down, 48, 28, w, h);
  REQUIRE(up.size() == codes.size());
  for (uint16_t c : down) CHECK(sent.count(c) == 1);
  for (uint16_t c : up) CHECK(sent.count(c) == 1);
  // The silhouette comes back where it was, to within the pixel the smaller size could not place.
  size_t user_sent = 0, user_back = 0, disagree = 0;
  for (size_t i = 0; i < codes.size(); ++i) {
    user_sent += codes[i] > 0;
    user_back += up[i] > 0;
    disagree += (codes[i] > 0) != (up[i] > 0);
  }
  CHECK(std::abs(double(user_back) - double(user_sent)) <= 0.1 * double(user_sent));
  CHECK(disagree <= 2 * (24 + 22));  // at most a pixel along the silhouette's perimeter
  // The same size is a copy; bad sizes are refused.
  CHECK(resample_codes_nearest(codes, w, h, w, h) == codes);
  CHECK_THROWS_AS(resample_codes_nearest(codes, w, h - 1, w, h), std::invalid_argument);
  CHECK_THROWS_AS(resample_codes_nearest(codes, w, h, 0, h), std::invalid_argument);
}

TEST_CASE("a received picture's size must be an even fraction of the call's", "[media][size]") {
  using rt::media::check_received_picture_size;
  CHECK(check_received_picture_size(1280, 720, 1280, 720).empty());
  CHECK(check_received_picture_size(960, 540, 1280, 720).empty());
  CHECK(check_received_picture_size(640, 360, 1280, 720).empty());
  CHECK_FALSE(check_received_picture_size(1282, 720, 1280, 720).empty());  // larger
  CHECK_FALSE(check_received_picture_size(961, 540, 1280, 720).empty());   // odd
  CHECK_FALSE(check_received_picture_size(160, 90, 1280, 720).empty());    // below a quarter
}
