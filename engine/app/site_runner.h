#pragma once
// One site of a two-site session (paper section 3.3, DESIGN.md section 1): its sender and its
// receiver, each stage in its own thread, joined by newest-wins mailboxes.
//
//   capture  (scene clock)  simulated or replayed RGBD frame -> mailbox ---------------------.
//   ibr      newest frame + remote eye -> portrait (RGBA + depth) -> network                 |
//   tracker  (50 Hz)        local skeletons -> network, touch loop; local eye -> network      |
//   network  remote eye -> ibr; remote skeletons -> history, touch loop; portraits -> mailbox |
//   hand     newest remote skeleton -> geometry hand (skinning, raster) at the portraits' view
//            -> short history of renders; each shown portrait -> appearance adaption (Eq. 3)
//   display  newest portrait + the hand render whose skeleton is closest in time to it ->
//            Eq. 4, Eq. 5, background -> PNG / MP4
//   touch    (50 Hz) local + remote skeletons -> touch start/end -> motor pulse, event to peer
//
// The scene plays on a shared clock: scene time = (now - connect time) * time_scale, so both
// sites' users move in step whatever the GPU manages; a stage that falls behind drops stale
// frames rather than queueing them. GPU work from all threads takes turns on one FairMutex.
#include <filesystem>
#include <string>

#include "app/options.h"
#include "geometry/site_frames.h"

namespace rt::app {

struct SiteRunOptions {
  RunOptions run;             // out (this site's folder), device, validation, width x height, frames
  bool frames_given = false;  // else the scene's own frame count
  std::string scene = "clap";
  Site site = Site::A;
  std::string listen = "127.0.0.1:0";  // listener: where to listen (port 0: any; printed as "listening on PORT")
  std::string peer;                    // connector: the listener's HOST:PORT; empty = be the listener
  std::filesystem::path key_file;      // 64 hex digits; both sites need the same
  double time_scale = 1.0;             // scene seconds per wall-clock second
  double resolution_scale = 0.0;       // of the cameras; 0 = the scene's own
  bool write_truth = true;             // this site's user seen from the remote eye, over the background
  double connect_timeout_s = 60.0;
  double linger_s = 1.5;  // after the last capture, how long without a new portrait ends the display
  // This site's devices: empty = simulated from the scene; else a recording (sim/recording.h) to
  // replay: its cameras, frames, times and tracker replace the scene's at this site.
  std::filesystem::path replay;
  std::string motor = "auto";  // simulated | usb | auto (the Arduino on USB when attached)
};

// Runs the site to the end of the scene; writes under run.out: frames/frame_NNNN.png,
// site.mp4, frames.jsonl (display index -> portrait frame), truth/frame_NNNN.png, events.jsonl,
// metrics.json. Prints "listening on PORT", "connected", "progress F N" and "done" lines on stdout
// for the demo's parent. Returns the exit code.
int run_site(const SiteRunOptions& options);

// Fills the fields a --config JSON names (scene, site, listen, peer, key_file, time_scale,
// resolution_scale, width, height, frames, replay, motor); a file path (key_file, replay) is
// relative to the config's folder.
// Throws naming the file and field.
void apply_site_config(const std::filesystem::path& config, SiteRunOptions& options);

}  // namespace rt::app
