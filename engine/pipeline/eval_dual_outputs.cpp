#include "pipeline/eval_dual_outputs.h"

#include "pipeline/plot_script.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <set>
#include <stdexcept>

#include "config/assets.h"
#include "image/image_io.h"

namespace rt::pipeline {
namespace {

using evaluation::TouchPhase;

// Room around the hand and forearm in a sheet's crop.
constexpr uint32_t kCropMarginPx = 24;

std::string csv_number(std::optional<double> value, const char* format = "%.4f") {
  if (!value || !std::isfinite(*value)) return "";
  char text[32];
  std::snprintf(text, sizeof text, format, *value);
  return text;
}

// What a viewer sees over black: premultiplied, opaque, 8 bits.
HostImage over_black(const HostImage& image, const PixelBox& box) {
  HostImage out(box.width, box.height, PixelFormat::RGBA8);
  for (uint32_t y = 0; y < box.height; ++y)
    for (uint32_t x = 0; x < box.width; ++x) {
      const uint32_t sx = box.x + x, sy = box.y + y;
      float alpha = image.at(sx, sy, 3);
      alpha = std::isfinite(alpha) ? std::clamp(alpha, 0.0f, 1.0f) : 0.0f;
      // The truth is premultiplied already (rgba8 from the simulator); the fused image is not.
      const float scale = image.format == PixelFormat::RGBA8 ? 1.0f : alpha;
      for (uint32_t c = 0; c < 3; ++c) {
        const float v = image.at(sx, sy, c) * scale;
        out.at(x, y, c) = std::isfinite(v) ? std::clamp(v, 0.0f, 1.0f) : 0.0f;
      }
      out.at(x, y, 3) = 1.0f;
    }
  return out;
}

struct Slot {
  const char* name;
  const char* title;
  TouchPhase phase;
  const char* variant;
};
// The panels of a sheet, in order.
const Slot kSlots[] = {{"far_image", "image-based, far", TouchPhase::Far, "image"},
                       {"approach_dual", "dual, approach", TouchPhase::Approach, "dual"},
                       {"glass_dual", "dual, at the glass", TouchPhase::Touching, "dual"},
                       {"glass_image", "image-based, at the glass", TouchPhase::Touching, "image"},
                       {"glass_dual_no_appearance", "dual without appearance adaption, at the glass", TouchPhase::Touching,
                        "dual_no_appearance"}};

// In the approach, the middle of the fusion ramp; elsewhere the frame that shows most of the
// hand and forearm. Lower is better.
double rank(const Slot& slot, const FrameRecord& record) {
  if (slot.phase == TouchPhase::Approach) return std::abs(record.distance_m - 0.3);
  return -double(record.hand_arm_pixels);
}

PixelBox hand_box(const evaluation::HandRegion& region) {
  uint32_t x0 = region.width, y0 = region.height, x1 = 0, y1 = 0;
  for (uint32_t y = 0; y < region.height; ++y)
    for (uint32_t x = 0; x < region.width; ++x)
      if (region.hand_arm[size_t(y) * region.width + x]) x0 = std::min(x0, x), y0 = std::min(y0, y), x1 = std::max(x1, x), y1 = std::max(y1, y);
  if (x0 > x1) return {};
  x0 = x0 > kCropMarginPx ? x0 - kCropMarginPx : 0;
  y0 = y0 > kCropMarginPx ? y0 - kCropMarginPx : 0;
  x1 = std::min(region.width - 1, x1 + kCropMarginPx);
  y1 = std::min(region.height - 1, y1 + kCropMarginPx);
  return {x0, y0, x1 - x0 + 1, y1 - y0 + 1};
}

}  // namespace

DualEvalOutputs::DualEvalOutputs(const std::filesystem::path& dir) : dir_(dir), csv_(dir / "frames.csv") {
  if (!csv_) throw std::runtime_error("eval dual: cannot write " + (dir / "frames.csv").string());
  csv_ << "user,scene_frame,t_s,d_m,tracked_d_m,phase,variant,psnr_hand_arm_db,psnr_user_db,ssim_hand_arm,de_hand,"
          "iou_hand_arm,tip_err_px,hand_arm_pixels,skeleton_gap_ms\n";
}

void DualEvalOutputs::add_frame(const FrameRecord& record, const std::string& variant, const evaluation::FrameScore& score,
                                std::optional<double> tip_error_px, const HostImage& shown, const HostImage& truth,
                                const evaluation::HandRegion& region) {
  csv_ << record.user << ',' << record.scene_frame << ',' << csv_number(record.time_s) << ',' << csv_number(record.distance_m)
       << ',' << csv_number(record.tracked_distance_m) << ',' << (record.phase ? evaluation::phase_name(*record.phase) : "")
       << ',' << variant << ',' << csv_number(score.psnr_db()) << ',' << csv_number(score.user_psnr_db()) << ','
       << csv_number(score.ssim()) << ',' << csv_number(score.delta_e()) << ',' << csv_number(score.iou()) << ','
       << csv_number(tip_error_px) << ',' << record.hand_arm_pixels << ','
       << csv_number(record.skeleton_gap_us ? std::optional<double>(double(*record.skeleton_gap_us) / 1000.0) : std::nullopt)
       << '\n';

  if (!record.phase || record.hand_arm_pixels == 0) return;
  for (const Slot& slot : kSlots) {
    if (slot.phase != *record.phase || variant != slot.variant) continue;
    const double r = rank(slot, record);
    auto found = chosen_.find({record.user, slot.name});
    if (found != chosen_.end() && found->second.rank <= r) continue;
    const PixelBox box = hand_box(region);
    if (box.empty()) continue;
    chosen_[{record.user, slot.name}] = Chosen{r, record, score.psnr_db(), over_black(shown, box), over_black(truth, box)};
  }
}

void DualEvalOutputs::finish() {
  csv_.flush();
  const std::filesystem::path sheet_dir = dir_ / "sheet";
  std::filesystem::create_directories(sheet_dir);
  nlohmann::json sheet = nlohmann::json::object();
  std::set<std::string> users;
  for (const auto& entry : chosen_) users.insert(entry.first.first);
  for (const std::string& user : users) {
    nlohmann::json panels = nlohmann::json::array();
    for (const Slot& slot : kSlots) {
      const auto found = chosen_.find({user, slot.name});
      if (found == chosen_.end()) continue;
      const Chosen& chosen = found->second;
      const std::string stem = user + "_" + slot.name;
      write_image(sheet_dir / (stem + ".png"), chosen.shown);
      write_image(sheet_dir / (stem + "_truth.png"), chosen.truth);
      panels.push_back({{"slot", slot.name},
                        {"title", slot.title},
                        {"image", stem + ".png"},
                        {"truth", stem + "_truth.png"},
                        {"scene_frame", chosen.record.scene_frame},
                        {"d_m", chosen.record.distance_m},
                        {"psnr_hand_arm_db", chosen.psnr_db ? nlohmann::json(*chosen.psnr_db) : nlohmann::json()}});
    }
    sheet[user] = panels;
  }
  std::ofstream(sheet_dir / "sheet.json") << sheet.dump(2) << "\n";
}

nlohmann::json check_goals(const nlohmann::json& report) {
  nlohmann::json goals = nlohmann::json::array();
  auto metric = [&](const std::string& user, const char* phase, const char* variant, const char* key) -> std::optional<double> {
    const auto& users = report.at("users");
    if (!users.contains(user) || !users[user].contains("phases")) return std::nullopt;
    const auto& phases = users[user]["phases"];
    if (!phases.contains(phase) || !phases[phase].contains(variant) || !phases[phase][variant].contains(key)) return std::nullopt;
    return phases[phase][variant][key].get<double>();
  };
  auto add = [&](const std::string& text, const std::string& user, std::optional<double> value, bool met) {
    goals.push_back({{"goal", text}, {"user", user}, {"value", *value}, {"met", met}});
  };
  // The darker-skinned user: the lower skin luminance.
  std::string darker;
  double darkest = 1e9;
  for (const auto& [user, data] : report.at("users").items()) {
    const auto& rgb = data.at("skin_rgb");
    const double y = 0.2126 * rgb[0].get<double>() + 0.7152 * rgb[1].get<double>() + 0.0722 * rgb[2].get<double>();
    if (y < darkest) darkest = y, darker = user;
  }
  for (const auto& [user, data] : report.at("users").items()) {
    (void)data;
    const auto dual = metric(user, "touching", "dual", "psnr_hand_arm_db");
    const auto image = metric(user, "touching", "image", "psnr_hand_arm_db");
    if (dual && image) add("touching: dual - image >= 6 dB (psnr_hand_arm_db)", user, *dual - *image, *dual - *image >= 6.0);
    const auto no_appearance = metric(user, "touching", "dual_no_appearance", "psnr_hand_arm_db");
    if (dual && no_appearance) {
      const double needed = user == darker ? 1.5 : 0.0;
      add(user == darker ? "touching: dual - dual_no_appearance >= 1.5 dB (the darker-skinned user)"
                         : "touching: dual - dual_no_appearance >= 0 dB",
          user, *dual - *no_appearance, *dual - *no_appearance >= needed);
    }
    const auto far_dual = metric(user, "far", "dual", "psnr_hand_arm_db");
    const auto far_image = metric(user, "far", "image", "psnr_hand_arm_db");
    if (far_dual && far_image)
      add("far: |dual - image| <= 0.2 dB", user, *far_dual - *far_image, std::abs(*far_dual - *far_image) <= 0.2);
    for (const char* phase : {"near", "touching"}) {
      const auto iou = metric(user, phase, "dual", "iou_hand_arm");
      if (iou) add(std::string(phase) + ": iou_hand_arm >= 0.8 (dual)", user, *iou, *iou >= 0.8);
    }
    const auto de = metric(user, "touching", "dual", "de_hand");
    if (de) add("touching: de_hand <= 6.5 (dual)", user, *de, *de <= 6.5);
  }
  return goals;
}

void print_summary(const nlohmann::json& report) {
  const auto& variants = report.at("variants");
  for (const auto& [user, data] : report.at("users").items()) {
    std::printf("\nuser %s as the other site sees them: psnr_hand_arm_db (de_hand, iou_hand_arm) per phase\n", user.c_str());
    std::printf("%-10s", "phase");
    for (const auto& v : variants) std::printf(" %22s", v.get<std::string>().c_str());
    std::printf(" %7s\n", "frames");
    for (const char* phase : evaluation::kTouchPhaseNames) {
      if (!data.contains("phases") || !data["phases"].contains(phase)) continue;
      const auto& row = data["phases"][phase];
      std::printf("%-10s", phase);
      size_t frames = 0;
      for (const auto& v : variants) {
        const std::string name = v.get<std::string>();
        if (!row.contains(name)) {
          std::printf(" %22s", "-");
          continue;
        }
        const auto& m = row[name];
        frames = m.value("frames", size_t(0));
        char cell[64];
        std::snprintf(cell, sizeof cell, "%.2f (%.1f, %.2f)", m.value("psnr_hand_arm_db", NAN), m.value("de_hand", NAN),
                      m.value("iou_hand_arm", NAN));
        std::printf(" %22s", cell);
      }
      std::printf(" %7zu\n", frames);
    }
  }
  std::printf("\ngoals:\n");
  for (const auto& goal : report.at("goals"))
    std::printf("  [%s] user %s: %s: %.3f\n", goal["met"].get<bool>() ? "met" : "NOT MET", goal["user"].get<std::string>().c_str(),
                goal["goal"].get<std::string>().c_str(), goal["value"].get<double>());
}

void plot_eval_dual(const std::filesystem::path& dir) {
  run_plot_script("plot_eval_dual.py", dir, "eval dual", "metrics.json and frames.csv are written; --no-plots skips the plots");
}

}  // namespace rt::pipeline
