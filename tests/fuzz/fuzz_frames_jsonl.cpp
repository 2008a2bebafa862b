// libFuzzer target: a recording's frames.jsonl (engine/sim/recording.cpp ReplayRgbdSource) from
// untrusted text, beside a fixed calibration.json (the default site, recorded at 1/50 of its
// resolution) and the images of frames 0 and 1, so that a well-formed line replays for real. The
// replay reads every listed frame's index and time, and plays the first few frames.
#include "fuzz_target.h"
#include "config/json.h"
#include "image/image_io.h"
#include "sim/recording.h"

namespace {

constexpr double kRecordedScale = 0.02;
constexpr size_t kFramesPlayed = 3;

const std::filesystem::path& recording_dir() {
  static const std::filesystem::path dir = [] {
    const std::filesystem::path made = rt::fuzz::work_dir() / "recording";
    std::filesystem::create_directories(made);
    nlohmann::json calibration = rt::config::read_json_file(rt::fuzz::assets_dir() / "sites" / "default.json");
    calibration["format"] = rt::sim::kRecordingFormat;
    calibration["recorded_scale"] = kRecordedScale;
    rt::config::write_json_file(made / "calibration.json", calibration);
    rt::fuzz::write_file(made / "frames.jsonl", "");
    const rt::sim::ReplayRgbdSource source(made);
    for (size_t k = 0; k < source.recorded_intrinsics().size(); ++k) {
      const auto& recorded = source.recorded_intrinsics()[k];
      for (uint64_t frame : {0, 1}) {
        std::filesystem::create_directories(rt::sim::color_path(made, k, frame).parent_path());
        rt::write_image(rt::sim::color_path(made, k, frame),
                        rt::HostImage(recorded.color.width, recorded.color.height, rt::PixelFormat::RGBA8, 0.5f));
        rt::write_image(rt::sim::depth_path(made, k, frame),
                        rt::HostImage(recorded.depth.width, recorded.depth.height, rt::PixelFormat::R16U, 900.0f));
      }
    }
    return made;
  }();
  return dir;
}

rt::fuzz::Outcome frames_jsonl(std::string_view input) {
  const std::filesystem::path& dir = recording_dir();
  rt::fuzz::write_file(dir / "frames.jsonl", input);
  return rt::fuzz::outcome_of([&] {
    rt::sim::ReplayRgbdSource source(dir);
    for (size_t i = 0; i < source.frame_count(); ++i) {
      source.frame_index(i);
      source.frame_timestamp_us(i);
    }
    for (size_t played = 0; played < kFramesPlayed; ++played) {
      const std::optional<rt::sim::RgbdFrame> frame = source.next_frame();
      if (!frame) break;
      if (frame->cameras.size() != source.recorded_intrinsics().size())
        rt::fuzz::fail("a replayed frame has " + std::to_string(frame->cameras.size()) + " cameras");
    }
  });
}

}  // namespace

RT_FUZZ_TARGET("frames_jsonl", frames_jsonl)
