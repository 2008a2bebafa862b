#!/usr/bin/env bash
# The av-marker scene end to end: session_demo.sh's checks (no touch anywhere), then each
# marker's clap against its flash at both sites, on screen and in site.mp4.
#   session_demo_av_marker.sh BINARY OUT
set -euo pipefail
binary=$1 out=$2
# On a CPU Vulkan driver (lavapipe) the cameras' tiny images draw faster on one thread each than
# handed between threads that both sites and the rest of the suite compete for: nearly every
# frame is shown, and the window can be judged. A GPU driver ignores it.
export LP_NUM_THREADS=${LP_NUM_THREADS:-1}
"$(dirname "$0")/session_demo.sh" "$binary" "$out" av-marker 115 0 --views 2
/usr/bin/python3 "$(dirname "$0")/check_av_marker.py" "$out"
