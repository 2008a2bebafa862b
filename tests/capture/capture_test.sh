#!/usr/bin/env bash
# Takes a capture of `remotetouch compose` frame 1, headless, and checks it in RenderDoc's replay.
#   capture_test.sh renderdoccmd|in-app REMOTETOUCH_BINARY OUTPUT_DIR
# renderdoccmd: as an engineer would, under `renderdoccmd capture`;
# in-app:       remotetouch loads librenderdoc.so itself.
set -euo pipefail
mode=$1 binary=$2 out=$3
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
# RenderDoc 1.24's own vkInvalidateMappedMemoryRanges calls trip the validation layer
# (VUID-VkMappedMemoryRange-size-01390) when both are loaded; those are not the engine's calls.
unset REMOTETOUCH_VALIDATION REMOTETOUCH_SYNC_VALIDATION
rm -rf "$out"
mkdir -p "$out"
demo=(compose --frames 3 --width 67 --height 41 --capture-frame 1 --out "$out")
case "$mode" in
  renderdoccmd)
    # renderdoccmd gives up when the launched process is slow to open RenderDoc's target-control
    # port, which a loaded CI machine does now and then: only that failure is tried again.
    for attempt in 1 2 3; do
      status=0
      renderdoccmd capture -w -c "$out/capture/rdc" "$binary" "${demo[@]}" 2>&1 | tee "$out/log.txt" || status=$?
      grep -q "RenderDoc injection failed" "$out/log.txt" || break
      echo "capture_test: RenderDoc could not attach (attempt $attempt), trying again" >&2
    done
    [ "$status" -eq 0 ] || exit "$status" ;;
  in-app) "$binary" "${demo[@]}" | tee "$out/log.txt" ;;
  *) echo "unknown mode $mode" >&2; exit 2 ;;
esac
grep -q "RenderDoc capture of frame 1" "$out/log.txt"
capture=$(find "$out/capture" -name '*.rdc' | head -n 1)
[ -n "$capture" ] || { echo "no .rdc written under $out/capture" >&2; exit 1; }
"$here/check_capture.sh" "$capture" \
  --passes "compose frame" hand_alpha overlay composite \
  --resources "hand mask" "hand alpha" portrait "hand color" fused background display hand_alpha overlay composite
