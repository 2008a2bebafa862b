#include "pipeline/accuracy_grid.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "config/json.h"

namespace rt::pipeline {

namespace {

constexpr uint32_t kMinPortraitSide = 16;

std::string joined(const std::vector<std::string>& words, const std::string& separator = " ") {
  std::string text;
  for (const std::string& word : words) text += (text.empty() ? "" : separator) + word;
  return text;
}

double parse_number(const std::string& name, const std::string& word) {
  size_t used = 0;
  double value = 0;
  try {
    value = std::stod(word, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != word.size() || !std::isfinite(value))
    throw std::invalid_argument("grid axis " + name + ": '" + word + "' is not a number");
  return value;
}

}  // namespace

std::pair<uint32_t, uint32_t> portrait_size(const AccuracyConfig& config, uint32_t base_width, uint32_t base_height) {
  auto side = [&](uint32_t base) {
    return std::max(kMinPortraitSide, uint32_t(std::lround(double(base) * config.portrait_scale)));
  };
  return {side(base_width), side(base_height)};
}

std::string accuracy_options(const AccuracyConfig& config, uint32_t base_width, uint32_t base_height) {
  std::vector<std::string> words = config::knob_arguments(ibr_knobs(), config.ibr, IbrSettings{});
  if (config.resolution_scale > 0) words.insert(words.end(), {"--resolution-scale", config::format_number(config.resolution_scale)});
  const auto [width, height] = portrait_size(config, base_width, base_height);
  if (width != base_width || height != base_height)
    words.insert(words.end(), {"--width", std::to_string(width), "--height", std::to_string(height)});
  return joined(words);
}

void set_axis(AccuracyConfig& config, const std::string& name, const std::string& word) {
  if (name == "resolution-scale") {
    config.resolution_scale = word == "scene" ? 0 : parse_number(name, word);
    if (config.resolution_scale < 0 || config.resolution_scale > 1)
      throw std::invalid_argument("grid axis resolution-scale: " + word + " is not in (0, 1] or scene");
    return;
  }
  if (name == "portrait-scale") {
    config.portrait_scale = parse_number(name, word);
    if (config.portrait_scale <= 0 || config.portrait_scale > 4)
      throw std::invalid_argument("grid axis portrait-scale: " + word + " is not in (0, 4]");
    return;
  }
  for (const auto& knob : ibr_knobs()) {
    if (knob.name != name) continue;
    const std::string wrong = "grid axis " + name + ": '" + word + "' is not " + config::knob_accepts(knob);
    switch (knob.kind) {
      case config::KnobKind::Flag:
        if (word != "on" && word != "off") throw std::invalid_argument("grid axis " + name + ": '" + word + "' is not on or off");
        knob.set(config.ibr, word == "on" ? 1 : 0);
        return;
      case config::KnobKind::Choice: {
        const auto found = std::find(knob.choices.begin(), knob.choices.end(), word);
        if (found == knob.choices.end()) throw std::invalid_argument(wrong);
        knob.set(config.ibr, double(found - knob.choices.begin()));
        return;
      }
      case config::KnobKind::Integer:
      case config::KnobKind::Real: {
        const double value = parse_number(name, word);
        if (value < knob.low || value > knob.high || (knob.kind == config::KnobKind::Integer && value != std::floor(value)))
          throw std::invalid_argument(wrong);
        knob.set(config.ibr, value);
        return;
      }
      case config::KnobKind::Text:
        knob.set_text(config.ibr, word);
        return;
    }
  }
  std::vector<std::string> names = {"resolution-scale", "portrait-scale"};
  for (const auto& knob : ibr_knobs()) names.push_back(knob.name);
  throw std::invalid_argument("unknown grid axis '" + name + "' (known: " + joined(names, ", ") + ")");
}

const std::vector<AccuracyGrid>& accuracy_grids() {
  // Blending by Lumi-Net is an axis of the full grid only: on a CPU driver its kernels take
  // seconds a frame, which would break the small grid's time bound. Its sizes (read from the
  // weights file) and arithmetic precision join as axes once they are knobs of ibr_knobs().
  static const std::vector<AccuracyGrid> grids = {
      {"tiny", "a handful of cheap configurations, for tests",
       {{"resolution-scale", {"0.25"}}, {"views", {"2"}}, {"fusion", {"avg"}}, {"refine", {"5"}},
        {"portrait-supersample", {"2"}}},
       {{"refine", {"0", "5"}}, {"portrait-supersample", {"1", "2"}}}},
      {"small", "every knob alone, then camera resolution x views x portrait supersampling",
       {{"portrait-scale", {"0.5"}},
        {"resolution-scale", {"0.25", "1"}},
        {"views", {"2", "6"}},
        {"fusion", {"avg"}},
        {"refine", {"5", "9"}},
        {"carve", {"on"}},
        {"portrait-supersample", {"2", "3"}},
        {"fill-holes", {"0"}}},
       {{"resolution-scale", {"scene", "1"}}, {"views", {"4", "6"}}, {"portrait-supersample", {"1", "3"}}}},
      {"full", "more values of every knob alone, then the product of the six that pay most",
       {{"portrait-scale", {"0.5", "2"}},
        {"resolution-scale", {"0.25", "0.75", "1"}},
        {"views", {"2", "6"}},
        {"fusion", {"avg"}},
        {"refine", {"5", "9", "13"}},
        {"carve", {"on"}},
        {"portrait-supersample", {"2", "3"}},
        {"edge-inset", {"0.3"}},
        {"best-views", {"2", "5"}},
        {"fill-holes", {"0", "4", "16"}},
        {"blend", {"lumi"}}},
       {{"resolution-scale", {"scene", "1"}},
        {"portrait-supersample", {"1", "3"}},
        {"refine", {"0", "9"}},
        {"views", {"4", "6"}},
        {"fusion", {"min", "avg"}},
        {"carve", {"off", "on"}}}},
  };
  return grids;
}

const AccuracyGrid& accuracy_grid(const std::string& name) {
  std::vector<std::string> names;
  for (const AccuracyGrid& grid : accuracy_grids()) {
    if (grid.name == name) return grid;
    names.push_back(grid.name);
  }
  throw std::invalid_argument("unknown grid '" + name + "' (known: " + joined(names, ", ") + ")");
}

std::vector<AccuracyConfig> expand_grid(const AccuracyGrid& grid) {
  std::vector<AccuracyConfig> configs;
  std::vector<std::string> seen;
  auto add = [&](const AccuracyConfig& config) {
    // The size words depend only on the scale, so any base size tells configurations apart.
    const std::string key = accuracy_options(config, 1000, 1000);
    if (std::find(seen.begin(), seen.end(), key) != seen.end()) return;
    seen.push_back(key);
    configs.push_back(config);
  };
  add(AccuracyConfig{});
  for (const GridAxis& axis : grid.one_at_a_time)
    for (const std::string& word : axis.values) {
      AccuracyConfig config;
      set_axis(config, axis.name, word);
      add(config);
    }
  size_t combinations = grid.product.empty() ? 0 : 1;
  for (const GridAxis& axis : grid.product) combinations *= axis.values.size();
  for (size_t index = 0; index < combinations; ++index) {
    AccuracyConfig config;
    size_t rest = index;
    // The last axis varies fastest, as in nested loops written in the table's order.
    for (size_t a = grid.product.size(); a-- > 0;) {
      const GridAxis& axis = grid.product[a];
      set_axis(config, axis.name, axis.values[rest % axis.values.size()]);
      rest /= axis.values.size();
    }
    add(config);
  }
  return configs;
}

}  // namespace rt::pipeline
