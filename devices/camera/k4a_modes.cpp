#include "camera/k4a_modes.h"

#include <array>
#include <stdexcept>

namespace rt::camera::k4a {

namespace {

struct DepthEntry {
  DepthMode mode;
  std::string_view name;
  SensorCut cut;
};
// The depth sensor is 1024x1024; the narrow modes crop its centre.
constexpr std::array<DepthEntry, 4> kDepthTable = {{
    {DepthMode::nfov_2x2_binned, "NFOV_2X2BINNED", {512, 512, 96, 90, 320, 288}},
    {DepthMode::nfov_unbinned, "NFOV_UNBINNED", {1024, 1024, 192, 180, 640, 576}},
    {DepthMode::wfov_2x2_binned, "WFOV_2X2BINNED", {512, 512, 0, 0, 512, 512}},
    {DepthMode::wfov_unbinned, "WFOV_UNBINNED", {1024, 1024, 0, 0, 1024, 1024}},
}};

struct ColorEntry {
  ColorResolution resolution;
  SensorCut cut;
};
// The colour sensor is 4:3; the 16:9 modes crop its middle rows.
constexpr std::array<ColorEntry, 6> kColorTable = {{
    {ColorResolution::p720, {1280, 960, 0, 120, 1280, 720}},
    {ColorResolution::p1080, {1920, 1440, 0, 180, 1920, 1080}},
    {ColorResolution::p1440, {2560, 1920, 0, 240, 2560, 1440}},
    {ColorResolution::p1536, {2048, 1536, 0, 0, 2048, 1536}},
    {ColorResolution::p2160, {3840, 2880, 0, 360, 3840, 2160}},
    {ColorResolution::p3072, {4096, 3072, 0, 0, 4096, 3072}},
}};

struct FormatEntry {
  ColorFormat format;
  std::string_view name;
  uint32_t fourcc;
};
constexpr std::array<FormatEntry, 4> kFormatTable = {{
    {ColorFormat::mjpg, "MJPG", 0x47504A4D},
    {ColorFormat::nv12, "NV12", 0x3231564E},
    {ColorFormat::yuy2, "YUY2", 0x32595559},
    {ColorFormat::bgra, "BGRA", 0x41524742},
}};

const DepthEntry& entry(DepthMode mode) {
  for (const DepthEntry& e : kDepthTable)
    if (e.mode == mode) return e;
  throw std::invalid_argument("k4a: unknown depth mode");
}
const ColorEntry& entry(ColorResolution resolution) {
  for (const ColorEntry& e : kColorTable)
    if (e.resolution == resolution) return e;
  throw std::invalid_argument("k4a: unknown colour resolution");
}
const FormatEntry& entry(ColorFormat format) {
  for (const FormatEntry& e : kFormatTable)
    if (e.format == format) return e;
  throw std::invalid_argument("k4a: unknown colour format");
}

}  // namespace

const SensorCut& sensor_cut(DepthMode mode) { return entry(mode).cut; }
const SensorCut& sensor_cut(ColorResolution resolution) { return entry(resolution).cut; }

std::string_view depth_mode_name(DepthMode mode) { return entry(mode).name; }
std::string_view color_format_name(ColorFormat format) { return entry(format).name; }

std::optional<DepthMode> depth_mode_from_name(std::string_view name) {
  for (const DepthEntry& e : kDepthTable)
    if (e.name == name) return e.mode;
  return std::nullopt;
}

std::optional<ColorFormat> color_format_from_name(std::string_view name) {
  for (const FormatEntry& e : kFormatTable)
    if (e.name == name) return e.format;
  return std::nullopt;
}

uint32_t color_fourcc(ColorFormat format) { return entry(format).fourcc; }

std::optional<ColorFormat> color_format_from_fourcc(uint32_t fourcc) {
  for (const FormatEntry& e : kFormatTable)
    if (e.fourcc == fourcc) return e.format;
  return std::nullopt;
}

std::string color_mode_tag(ColorFormat format, ColorResolution resolution) {
  return std::string(color_format_name(format)) + "_" + std::to_string(sensor_cut(resolution).output_height) + "P";
}

std::optional<ColorMode> color_mode_from_tag(std::string_view tag) {
  for (const FormatEntry& f : kFormatTable)
    for (const ColorEntry& c : kColorTable)
      if (color_mode_tag(f.format, c.resolution) == tag) return ColorMode{f.format, c.resolution};
  return std::nullopt;
}

std::optional<DepthMode> depth_mode_for_size(uint32_t width, uint32_t height) {
  for (const DepthEntry& e : kDepthTable)
    if (e.cut.output_width == width && e.cut.output_height == height) return e.mode;
  return std::nullopt;
}

std::optional<ColorResolution> color_resolution_for_size(uint32_t width, uint32_t height) {
  for (const ColorEntry& e : kColorTable)
    if (e.cut.output_width == width && e.cut.output_height == height) return e.resolution;
  return std::nullopt;
}

std::string depth_mode_sizes() {
  std::string text;
  for (const DepthEntry& e : kDepthTable) {
    if (!text.empty()) text += ", ";
    text += std::to_string(e.cut.output_width) + "x" + std::to_string(e.cut.output_height) + " (" +
            std::string(e.name) + ")";
  }
  return text;
}

std::string color_resolution_sizes() {
  std::string text;
  for (const ColorEntry& e : kColorTable) {
    if (!text.empty()) text += ", ";
    text += std::to_string(e.cut.output_width) + "x" + std::to_string(e.cut.output_height);
  }
  return text;
}

bool is_frame_rate(uint32_t fps) {
  for (uint32_t rate : kFrameRates)
    if (rate == fps) return true;
  return false;
}

std::optional<uint32_t> frame_rate_for_period(uint64_t period_ns) {
  if (period_ns == 0) return std::nullopt;
  // Rounded, not truncated: a period rounded up by a nanosecond (15 fps as 66,666,667 ns) is
  // still that rate.
  const uint64_t fps = (1'000'000'000ull + period_ns / 2) / period_ns;
  for (uint32_t rate : kFrameRates)
    if (rate == fps) return rate;
  return std::nullopt;
}

}  // namespace rt::camera::k4a
