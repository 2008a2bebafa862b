// The pieces of `eval dual` that decide what is measured where: the touch phases, the
// hand+forearm region from the truth, and the scores on it, on synthetic cases with known answers.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

#include "evaluation/region_scores.h"
#include "evaluation/touch_phase.h"
#include "image/pixel_mask.h"
#include "shared/config.h"

using namespace rt;
using namespace rt::evaluation;

TEST_CASE("touch phases split at 0.4, 0.2 and 0.02 m, lower bounds inclusive") {
  CHECK(touch_phase(1.0) == TouchPhase::Far);
  CHECK(touch_phase(0.4) == TouchPhase::Far);
  CHECK(touch_phase(0.3999) == TouchPhase::Approach);
  CHECK(touch_phase(0.2) == TouchPhase::Approach);
  CHECK(touch_phase(0.1999) == TouchPhase::Near);
  CHECK(touch_phase(0.02) == TouchPhase::Near);
  CHECK(touch_phase(0.0199) == TouchPhase::Touching);
  CHECK(touch_phase(-0.01) == TouchPhase::Touching);  // pressed into the glass
  CHECK_FALSE(touch_phase(std::numeric_limits<double>::quiet_NaN()));
  CHECK_FALSE(touch_phase(std::numeric_limits<double>::infinity()));
  CHECK(std::string(phase_name(TouchPhase::Approach)) == "approach");
}

TEST_CASE("dilate_mask grows a pixel into a clipped square") {
  PixelMask mask(7 * 5, 0);
  mask[1 * 7 + 0] = 1;  // at the left edge
  const PixelMask grown = dilate_mask(mask, 7, 5, 2);
  CHECK(count_set(grown) == 3 * 4);  // columns 0-2, rows 0-3
  CHECK(count_set(dilate_mask(mask, 7, 5, 0)) == 1);
  CHECK(count_set(dilate_mask(PixelMask(35, 0), 7, 5, 3)) == 0);
}

namespace {

// A 23x17 view: the body at 1 m on the left half; the measured limb at 0.5 m in rows 4-8,
// columns 6-14 (hand in 6-10, forearm 11-14); something else at 0.4 m in front of columns
// 13-14 (the other hand); the hand's column 6 only half covered.
struct Synthetic {
  static constexpr uint32_t w = 23, h = 17;
  HostImage scene_color{w, h, PixelFormat::RGBA8}, scene_depth{w, h, PixelFormat::R32F}, scene_part{w, h, PixelFormat::R32F};
  HostImage limb_depth{w, h, PixelFormat::R32F}, limb_part{w, h, PixelFormat::R32F};
  Synthetic() {
    for (uint32_t y = 0; y < h; ++y)
      for (uint32_t x = 0; x < w; ++x) {
        auto paint = [&](float z, float part, float gray, float alpha) {
          scene_depth.at(x, y) = z;
          scene_part.at(x, y) = part;
          for (uint32_t c = 0; c < 3; ++c) scene_color.at(x, y, c) = gray * alpha;
          scene_color.at(x, y, 3) = alpha;
        };
        if (x < w / 2) paint(1.0f, float(RT_PART_BODY), 0.3f, 1.0f);
        const bool limb = y >= 4 && y <= 8 && x >= 6 && x <= 14;
        if (limb) {
          limb_depth.at(x, y) = 0.5f;
          limb_part.at(x, y) = x <= 10 ? float(RT_PART_HAND) : float(RT_PART_BODY);
          paint(0.5f, limb_part.at(x, y), 0.6f, x == 6 ? 0.5f : 1.0f);
        }
        if (y >= 4 && y <= 8 && x >= 13 && x <= 14) paint(0.4f, float(RT_PART_HAND), 0.8f, 1.0f);
      }
  }
  HandRegion region() const { return hand_region(scene_color, scene_depth, scene_part, limb_depth, limb_part); }
};

}  // namespace

TEST_CASE("the hand region is the visible limb; the hand alone is its fully covered hand pixels") {
  const Synthetic s;
  const HandRegion region = s.region();
  CHECK(count_set(region.hand_arm) == 5 * 7);  // columns 6-12: 13-14 are hidden
  CHECK(count_set(region.hand) == 5 * 4);      // columns 7-10: column 6 is an edge
  CHECK_FALSE(region.hand_arm[6 * Synthetic::w + 13]);
  // Dilated by 3: columns 3-15, rows 1-11.
  CHECK(count_set(region.region) == 13 * 11);
  CHECK(count_set(region.silhouette) >= count_set(region.region));
  CHECK(count_set(region.user) == Synthetic::h * (Synthetic::w / 2) + 5 * (15 - 11));
}

TEST_CASE("a limb depth that is NaN, zero or behind the scene is not part of the region") {
  Synthetic s;
  s.limb_depth.at(8, 6) = std::numeric_limits<float>::quiet_NaN();
  s.limb_depth.at(9, 6) = 0.0f;
  s.limb_depth.at(10, 6) = 0.7f;  // the scene has 0.5 there: something is in front
  CHECK(count_set(s.region().hand_arm) == 5 * 7 - 3);
  HostImage small(3, 3, PixelFormat::R32F);
  CHECK_THROWS_AS(hand_region(s.scene_color, s.scene_depth, s.scene_part, small, s.limb_part), std::invalid_argument);
}

TEST_CASE("scores: identical images are perfect, a known error gives its PSNR, broken pixels stay finite") {
  const Synthetic s;
  const HandRegion region = s.region();
  // The truth as the receiver's straight-alpha image.
  HostImage shown(Synthetic::w, Synthetic::h, PixelFormat::RGBA32F);
  for (uint32_t y = 0; y < Synthetic::h; ++y)
    for (uint32_t x = 0; x < Synthetic::w; ++x) {
      const float alpha = s.scene_color.at(x, y, 3);
      for (uint32_t c = 0; c < 3; ++c) shown.at(x, y, c) = alpha > 0 ? s.scene_color.at(x, y, c) / alpha : 0.0f;
      shown.at(x, y, 3) = alpha;
    }
  const FrameScore same = score_frame(shown, s.scene_color, region);
  REQUIRE(same.psnr_db());
  CHECK(*same.psnr_db() == Approx(99.0));
  CHECK(*same.ssim() == Approx(1.0).margin(1e-9));
  CHECK(*same.delta_e() == Approx(0.0).margin(1e-9));
  CHECK(*same.iou() == Approx(1.0));

  // Every channel of every region pixel 0.1 brighter (none clips): MSE 0.01, 20 dB.
  HostImage brighter = shown;
  for (uint32_t y = 0; y < Synthetic::h; ++y)
    for (uint32_t x = 0; x < Synthetic::w; ++x) {
      if (!region.region[y * Synthetic::w + x]) continue;
      // Opaque, premultiplied and straight alike: the truth's premultiplied color plus 0.1.
      brighter.at(x, y, 3) = 1.0f;
      for (uint32_t c = 0; c < 3; ++c) brighter.at(x, y, c) = s.scene_color.at(x, y, c) + 0.1f;
    }
  const FrameScore off = score_frame(brighter, s.scene_color, region);
  CHECK(*off.psnr_db() == Approx(20.0).margin(0.01));
  CHECK(*off.delta_e() > 1.0);
  CHECK(*off.iou() < 1.0);  // the background around the limb became opaque
  CHECK(*off.ssim() < 1.0);

  HostImage broken = shown;
  broken.at(8, 6, 0) = std::numeric_limits<float>::quiet_NaN();
  broken.at(9, 6, 3) = std::numeric_limits<float>::infinity();
  const FrameScore b = score_frame(broken, s.scene_color, region);
  CHECK(std::isfinite(*b.psnr_db()));
  CHECK(*b.psnr_db() < 99.0);
  CHECK(std::isfinite(*b.ssim()));
  CHECK(std::isfinite(*b.delta_e()));
  CHECK(std::isfinite(*b.iou()));
}

TEST_CASE("pooled scores leave out what has no pixels, and never write NaN") {
  const Synthetic s;
  HandRegion empty = s.region();
  std::fill(empty.region.begin(), empty.region.end(), 0);
  std::fill(empty.hand.begin(), empty.hand.end(), 0);
  std::fill(empty.silhouette.begin(), empty.silhouette.end(), 0);
  const HostImage shown(Synthetic::w, Synthetic::h, PixelFormat::RGBA32F);
  const FrameScore score = score_frame(shown, s.scene_color, empty);
  CHECK_FALSE(score.psnr_db());
  CHECK_FALSE(score.ssim());
  CHECK_FALSE(score.delta_e());
  CHECK_FALSE(score.iou());
  ScoreTotals totals;
  totals.add(score, std::nullopt);
  totals.add(score, std::numeric_limits<double>::quiet_NaN());
  const auto json = totals.to_json();
  CHECK(json.at("frames") == 2);
  CHECK_FALSE(json.contains("psnr_hand_arm_db"));
  CHECK_FALSE(json.contains("tip_err_px"));
  CHECK(json.contains("psnr_user_db"));  // the body is there
  totals.add(score, 2.0);
  totals.add(score, 4.0);
  CHECK(totals.to_json().at("tip_err_px").get<double>() == Approx(3.0));
}

TEST_CASE("a recorded region decodes to the same hand, forearm and dilated masks") {
  const Synthetic s;
  const HandRegion region = s.region();
  const HandRegion decoded = decode_region(encode_region(region));
  CHECK(decoded.hand_arm == region.hand_arm);
  CHECK(decoded.hand == region.hand);
  CHECK(decoded.region == region.region);
  CHECK(decoded.silhouette == region.silhouette);
  HostImage rgba(4, 4, PixelFormat::RGBA32F);
  CHECK_THROWS_AS(decode_region(rgba), std::invalid_argument);
  HostImage nan(4, 4, PixelFormat::R32F, std::numeric_limits<float>::quiet_NaN());
  CHECK(count_set(decode_region(nan).hand_arm) == 0);
}
