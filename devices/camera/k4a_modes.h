#pragma once
// The camera modes of the Azure Kinect / Orbbec Femto (the k4a C API): how each depth mode and
// colour resolution is cut from its sensor, the names the recordings' tags use for them, and
// the frame rates a recording may have. The sensor geometry decides the intrinsics at a mode
// (k4a_calibration.h), so it lives here once, beside the names.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace rt::camera::k4a {

enum class DepthMode { nfov_2x2_binned, nfov_unbinned, wfov_2x2_binned, wfov_unbinned };
enum class ColorResolution { p720, p1080, p1440, p1536, p2160, p3072 };
enum class ColorFormat { mjpg, nv12, yuy2, bgra };

// A mode's image is the sensor scaled to `binned` pixels, then cropped from `crop` to `output`.
struct SensorCut {
  uint32_t binned_width, binned_height;
  int32_t crop_x, crop_y;
  uint32_t output_width, output_height;
};

const SensorCut& sensor_cut(DepthMode mode);
const SensorCut& sensor_cut(ColorResolution resolution);

inline constexpr DepthMode kDepthModes[] = {DepthMode::nfov_2x2_binned, DepthMode::nfov_unbinned,
                                            DepthMode::wfov_2x2_binned, DepthMode::wfov_unbinned};
inline constexpr ColorResolution kColorResolutions[] = {ColorResolution::p720,  ColorResolution::p1080,
                                                        ColorResolution::p1440, ColorResolution::p1536,
                                                        ColorResolution::p2160, ColorResolution::p3072};

// The tag values: "NFOV_UNBINNED", "MJPG" (as in "MJPG_720P").
std::string_view depth_mode_name(DepthMode mode);
std::string_view color_format_name(ColorFormat format);
std::optional<DepthMode> depth_mode_from_name(std::string_view name);
std::optional<ColorFormat> color_format_from_name(std::string_view name);
// The image's FourCC in a track's BITMAPINFOHEADER (biCompression, little-endian bytes).
uint32_t color_fourcc(ColorFormat format);
std::optional<ColorFormat> color_format_from_fourcc(uint32_t fourcc);
inline constexpr uint32_t kDepthFourcc = 0x67363162;  // "b16g": 16-bit grey, big-endian

// "MJPG_720P" <-> format and resolution; empty when the text names no mode.
std::string color_mode_tag(ColorFormat format, ColorResolution resolution);
struct ColorMode {
  ColorFormat format;
  ColorResolution resolution;
};
std::optional<ColorMode> color_mode_from_tag(std::string_view tag);

// The mode whose output image has exactly this size; depth modes of equal size (WFOV 2x2 binned
// and nothing else is 512x512) do not collide.
std::optional<DepthMode> depth_mode_for_size(uint32_t width, uint32_t height);
std::optional<ColorResolution> color_resolution_for_size(uint32_t width, uint32_t height);
// "1280x720 (MJPG_720P), ..." for error messages that list what would have been accepted.
std::string depth_mode_sizes();
std::string color_resolution_sizes();

// The recordings' frame rates, and the DefaultDuration of a track at each (whole nanoseconds,
// truncated as the recorder does).
inline constexpr uint32_t kFrameRates[] = {5, 15, 30};
bool is_frame_rate(uint32_t fps);
inline uint64_t frame_period_ns(uint32_t fps) { return 1'000'000'000ull / fps; }
// The frame rate whose period is `period_ns`, as the SDK's playback decides it; empty for none.
std::optional<uint32_t> frame_rate_for_period(uint64_t period_ns);

}  // namespace rt::camera::k4a
