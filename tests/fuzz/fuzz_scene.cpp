// libFuzzer target: a scene file (engine/sim/scene.cpp load_scene) from untrusted text. It is
// written as scenes/fuzz.json beside a copy of assets/sites/, so that "../sites/default.json"
// names a real site file as in assets/scenes/. An accepted scene's motions must be playable.
#include <cmath>

#include "fuzz_target.h"
#include "sim/scene.h"

namespace {

const std::filesystem::path& scene_path() {
  static const std::filesystem::path path = [] {
    const std::filesystem::path dir = rt::fuzz::work_dir() / "scene";
    std::filesystem::create_directories(dir / "scenes");
    std::filesystem::copy(rt::fuzz::assets_dir() / "sites", dir / "sites", std::filesystem::copy_options::recursive);
    return dir / "scenes" / "fuzz.json";
  }();
  return path;
}

rt::fuzz::Outcome scene(std::string_view input) {
  const std::filesystem::path& path = scene_path();
  rt::fuzz::write_file(path, input);
  rt::sim::Scene loaded;
  const rt::fuzz::Outcome outcome = rt::fuzz::outcome_of([&] { loaded = rt::sim::load_scene(path); });
  if (outcome.accepted) {
    if (loaded.frame_count < 1 || !(loaded.fps >= 1.0) || loaded.color_supersampling % 2 == 0)
      rt::fuzz::fail("accepted a scene of " + std::to_string(loaded.frame_count) + " frames at " +
                     std::to_string(loaded.fps) + " fps, supersampling " + std::to_string(loaded.color_supersampling));
    for (rt::Site site : {rt::Site::A, rt::Site::B}) {
      const rt::sim::MotionTrack track = rt::sim::make_motion_track(loaded, site);
      if (!std::isfinite(track.duration_s())) rt::fuzz::fail("accepted a motion of non-finite duration");
      track.pose_at(0.5 * track.duration_s());
    }
  }
  return outcome;
}

}  // namespace

RT_FUZZ_TARGET("scene", scene)
