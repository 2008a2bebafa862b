// The loss-based bitrate rule (media/bitrate_rule.h): down quickly on loss or a long round trip,
// up slowly on clean reports, held in between, never past its floor or ceiling; bad reports and
// bad options refused.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <stdexcept>

#include "media/bitrate_rule.h"

using rt::media::BitrateRule;
using rt::media::BitrateRuleOptions;

TEST_CASE("the bitrate rule lowers on loss, raises when clean and holds in between", "[media][bitrate]") {
  BitrateRuleOptions options;
  options.start_kbps = 1000;
  options.floor_kbps = 300;
  options.ceiling_kbps = 2000;
  BitrateRule rule(options);
  CHECK(rule.kbps() == 1000);
  CHECK(rule.on_report(0.05, 0.01) == 850);  // 5 % lost: down by the lowering factor
  CHECK(rule.on_report(0.015, 0.01) == 850);  // between clean and high: held
  CHECK(rule.on_report(0.02, 0.01) == 850);   // exactly at the threshold: held
  CHECK(rule.on_report(0.0, 0.01) == 893);    // clean: up 5 %
  CHECK(rule.on_report(0.0, 0.9) == 759);     // a round trip past 0.4 s: down as for loss
  CHECK(rule.lowered() == 2);
  CHECK(rule.raised() == 1);
  for (int i = 0; i < 100; ++i) rule.on_report(0.5, 0.01);
  CHECK(rule.kbps() == 300);  // the floor
  for (int i = 0; i < 200; ++i) rule.on_report(0.0, -1);  // no round trip known yet: loss alone decides
  CHECK(rule.kbps() == 2000);  // the ceiling
  const uint64_t raised = rule.raised();
  rule.on_report(0.0, 0.01);
  CHECK(rule.raised() == raised);  // at the ceiling a clean report raises nothing
}

TEST_CASE("the bitrate rule ignores reports that say nothing and refuses bad options", "[media][bitrate]") {
  BitrateRule rule{BitrateRuleOptions{}};
  const int start = rule.kbps();
  CHECK(rule.on_report(std::numeric_limits<double>::quiet_NaN(), 0.01) == start);
  CHECK(rule.on_report(-0.1, 0.01) == start);
  CHECK(rule.on_report(1.5, 0.01) == start);
  CHECK(rule.lowered() == 0);
  const auto refused = [](auto change) {
    BitrateRuleOptions o;
    change(o);
    CHECK_FALSE(rt::media::check_bitrate_rule(o).empty());
    CHECK_THROWS_AS(BitrateRule(o), std::invalid_argument);
  };
  refused([](BitrateRuleOptions& o) { o.floor_kbps = 10; });
  refused([](BitrateRuleOptions& o) { o.ceiling_kbps = o.floor_kbps - 1; });
  refused([](BitrateRuleOptions& o) { o.start_kbps = o.ceiling_kbps + 1; });
  refused([](BitrateRuleOptions& o) { o.loss_clean = 0.5; });
  refused([](BitrateRuleOptions& o) { o.lower_factor = 1.0; });
  refused([](BitrateRuleOptions& o) { o.raise_factor = 0.9; });
  refused([](BitrateRuleOptions& o) { o.round_trip_high_s = std::numeric_limits<double>::quiet_NaN(); });
  CHECK(rt::media::check_bitrate_rule(BitrateRuleOptions{}).empty());
}
