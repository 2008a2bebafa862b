#include "site/displayed_truth.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>

#include "evaluation/region_scores.h"
#include "image/image_io.h"
#include "site/site_display.h"

namespace rt::site {
namespace {

std::string region_name(uint64_t frame) {
  char name[32];
  std::snprintf(name, sizeof name, "hand_%04llu.png", static_cast<unsigned long long>(frame));
  return name;
}

std::optional<HostImage> read_if_there(const std::filesystem::path& path) {
  if (!std::filesystem::exists(path)) return std::nullopt;
  try {
    return read_image(path);
  } catch (const std::exception&) {
    return std::nullopt;  // a frame being written as the run ended: left out
  }
}

// An opaque RGB image (a displayed frame, a truth over the background) as RGBA with alpha 1.
HostImage opaque(const HostImage& image) {
  if (image.channels() == 4) {
    HostImage out = image;
    for (uint32_t y = 0; y < out.height; ++y)
      for (uint32_t x = 0; x < out.width; ++x) out.at(x, y, 3) = 1.0f;
    return out;
  }
  return image;
}

// PSNR over the RGB of two images of one size, values in [0, 1]; identical images give a capped,
// finite 99 dB.
double whole_frame_psnr_db(const HostImage& a, const HostImage& b) {
  double squared = 0;
  size_t values = 0;
  for (uint32_t y = 0; y < a.height; ++y)
    for (uint32_t x = 0; x < a.width; ++x)
      for (uint32_t c = 0; c < 3; ++c) {
        const double d = double(a.at(x, y, std::min(c, a.channels() - 1))) - double(b.at(x, y, std::min(c, b.channels() - 1)));
        squared += d * d;
        ++values;
      }
  const double mse = values ? squared / double(values) : 0.0;
  return mse > 0 ? 10.0 * std::log10(1.0 / mse) : 99.0;
}

}  // namespace

TruthRegionWriter::TruthRegionWriter(const std::filesystem::path& truth_dir)
    : dir_(truth_dir), lines_(truth_dir / "hands.jsonl") {}

void TruthRegionWriter::write(uint64_t frame, const evaluation::HandRegion& region, double distance_m,
                              std::optional<evaluation::TouchPhase> phase) {
  write_image(dir_ / region_name(frame), evaluation::encode_region(region));
  lines_ << nlohmann::json{{"frame", frame},
                           {"d_m", std::isfinite(distance_m) ? nlohmann::json(distance_m) : nlohmann::json()},
                           {"phase", phase ? nlohmann::json(evaluation::phase_name(*phase)) : nlohmann::json()}}
                .dump()
         << "\n";
  lines_.flush();
}

nlohmann::json measure_displayed_frames(const std::filesystem::path& shown, const std::filesystem::path& captured) {
  std::map<uint64_t, std::string> phases;
  {
    std::ifstream lines(captured / "truth" / "hands.jsonl");
    for (std::string line; std::getline(lines, line);) {
      const nlohmann::json entry = nlohmann::json::parse(line, nullptr, false);
      if (entry.is_discarded() || !entry.contains("frame") || !entry["frame"].is_number_unsigned() || !entry["phase"].is_string())
        continue;
      phases[entry["frame"].get<uint64_t>()] = entry["phase"].get<std::string>();
    }
  }
  std::ifstream frames(shown / "frames.jsonl");
  std::vector<double> whole_frame_db;
  double final_db = NAN;
  nlohmann::json final_frame;
  std::map<std::string, evaluation::ScoreTotals> by_phase;
  for (std::string line; std::getline(frames, line);) {
    const nlohmann::json entry = nlohmann::json::parse(line, nullptr, false);
    if (entry.is_discarded() || !entry["portrait_frame"].is_number_unsigned()) continue;  // e.g. a link-lost frame
    const uint64_t portrait_frame = entry["portrait_frame"].get<uint64_t>();
    const std::filesystem::path display = shown / "frames" / frame_name(entry["display"].get<uint64_t>());
    const std::filesystem::path truth = captured / "truth" / frame_name(portrait_frame);
    // Each image is read once: for the whole frame's PSNR and, in a phase, for the hand's region.
    const auto shown_image = read_if_there(display), truth_image = read_if_there(truth);
    if (!shown_image || !truth_image || truth_image->width != shown_image->width || truth_image->height != shown_image->height)
      continue;
    const double db = whole_frame_psnr_db(*shown_image, *truth_image);
    whole_frame_db.push_back(db);
    final_db = db;
    final_frame = {{"display", display.string()}, {"truth", truth.string()}};

    const auto phase = phases.find(portrait_frame);
    if (phase == phases.end()) continue;
    const auto region_image = read_if_there(captured / "truth" / region_name(portrait_frame));
    if (!region_image || region_image->width != shown_image->width || region_image->height != shown_image->height) continue;
    const evaluation::HandRegion region = evaluation::decode_region(*region_image);
    by_phase[phase->second].add(evaluation::score_frame(opaque(*shown_image), opaque(*truth_image), region), std::nullopt);
  }
  double mean = NAN;
  if (!whole_frame_db.empty()) {
    mean = 0;
    for (double v : whole_frame_db) mean += v / double(whole_frame_db.size());
  }
  auto number = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); };
  nlohmann::json out = {{"final_db", number(final_db)},
                        {"mean_db", number(mean)},
                        {"frames", whole_frame_db.size()},
                        {"final_frame", final_frame}};
  for (const auto& [phase, totals] : by_phase) {
    nlohmann::json figures = totals.to_json();
    figures.erase("iou_hand_arm");  // over the background every pixel is opaque: no silhouette
    figures.erase("psnr_user_db");  // not recorded
    out["hand_arm"][phase] = figures;
  }
  return out;
}

}  // namespace rt::site
