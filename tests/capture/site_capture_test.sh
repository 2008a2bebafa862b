#!/usr/bin/env bash
# RenderDoc captures of running sites: `remotetouch demo --capture-frame 2 --profile` at a tiny
# size; each site writes one capture of its sender's iteration and one of its receiver's, which
# RenderDoc's replay opens and where the image-based model's and the compositing's passes appear
# by name; --profile prints each graph's per-pass GPU times. Half speed: a loaded machine, or one
# compiling changed pipelines, still runs the sender past its third iteration.
#   site_capture_test.sh REMOTETOUCH_BINARY OUTPUT_DIR
set -euo pipefail
binary=$1 out=$2
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
# RenderDoc's own vkInvalidateMappedMemoryRanges calls trip the validation layer (capture_test.sh).
unset REMOTETOUCH_VALIDATION REMOTETOUCH_SYNC_VALIDATION
rm -rf "$out"
fail() { echo "FAIL: $*" >&2; exit 1; }
"$binary" demo --frames 60 --width 96 --height 54 --resolution-scale 0.1 --time-scale 0.5 --capture-frame 2 --profile \
  --out "$out" 2>&1 | tee "$out.log"
for site in A B; do
  grep -q "\[site $site\] site $site, ibr: GPU ms per pass" "$out.log" || fail "site $site printed no profile of its ibr graph"
  grep -Eq "\[site $site\]   receiver_composite +[0-9]+\.[0-9]+" "$out.log" || fail "site $site's profile has no receiver_composite pass"
  sender=$(/usr/bin/python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['capture']['sender'] or '')" "$out/site_$site/metrics.json")
  receiver=$(/usr/bin/python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['capture']['receiver'] or '')" "$out/site_$site/metrics.json")
  [ -s "$sender" ] || fail "site $site: no sender capture ($sender)"
  [ -s "$receiver" ] || fail "site $site: no receiver capture ($receiver)"
  grep -q "RenderDoc capture of site $site's sender at frame 2: $sender" "$out.log" || fail "site $site does not say where its capture is"
  "$here/check_capture.sh" "$sender" --passes "image-based model" ibr_foreground ibr_splat ibr_fuse ibr_warp_blend \
    --resources portrait
  "$here/check_capture.sh" "$receiver" --passes "receiver frame" receiver_composite \
    --resources portrait "hand mask" display
done
echo "both sites captured their sender and receiver iterations"
