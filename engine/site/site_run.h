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

#include "site/site_options.h"

namespace rt::site {

// Runs the site to the end of the scene; writes under run.out: frames/frame_NNNN.png,
// site.mp4, frames.jsonl (display index -> portrait frame), truth/frame_NNNN.png, events.jsonl,
// metrics.json. Prints "listening on PORT", "connected", "progress F N" and "done" lines on stdout
// for the demo's parent. Returns the exit code.
int run_site(const SiteRunOptions& options);

}  // namespace rt::site
