#!/usr/bin/env bash
# A site's cameras as k4a recordings, played where a user plays them:
#   `simulate --format k4a` writes wave's site A (4 frames at the cameras' own k4a modes), then
#   `eval ibr --cameras-from` renders the portraits from those recordings and from the simulator,
#   which must agree within 0.3 dB on the foreground and the hand (the MJPG is the only
#   difference) with the same depth error; and `demo --replay-a` plays the recordings as site A
#   in a call: portraits reach site B.
#   k4a_site_played.sh BINARY OUT
set -euo pipefail
binary=$1 out=$2
rm -rf "$out"
mkdir -p "$out"
fail() { echo "FAIL: $*" >&2; exit 1; }

"$binary" simulate --scene wave --format k4a --resolution-scale 1 --supersample 3 --frames 4 --gt-width 64 \
  --gt-height 36 --out "$out/recordings" > "$out/simulate.out"
eval_args=(eval ibr --scene wave --resolution-scale 1 --frames 4 --width 320 --height 180)
"$binary" "${eval_args[@]}" --out "$out/simulated" > "$out/simulated.out"
"$binary" "${eval_args[@]}" --cameras-from "$out/recordings" --out "$out/k4a" > "$out/k4a.out"
grep -q "cameras' images from k4a recordings '$out/recordings'" "$out/k4a.out" || fail "eval ibr did not say it plays the recordings"
/usr/bin/python3 - "$out" <<'PY' || fail "the portraits from the recordings differ from the simulator's"
import json, math, sys
out = sys.argv[1]
simulated = json.load(open(f"{out}/simulated/metrics.json"))
k4a = json.load(open(f"{out}/k4a/metrics.json"))
assert k4a["cameras_from"] == f"{out}/recordings", k4a["cameras_from"]
for key, tolerance in (("psnr_fg_db", 0.3), ("psnr_hand_db", 0.3), ("depth_mae_edge_mm", 0.05)):
    a, b = simulated[key], k4a[key]
    print(f"{key}: simulator {a:.3f}, k4a recordings {b:.3f}, difference {b - a:+.3f} (tolerance {tolerance})")
    assert math.isfinite(a) and math.isfinite(b), key
    assert abs(b - a) <= tolerance, key
PY

"$binary" demo --scene wave --replay-a "$out/recordings" --frames 4 --width 64 --height 36 --display headless \
  --out "$out/demo" > "$out/demo.out" 2> "$out/demo.err" || { cat "$out/demo.err"; fail "the demo failed"; }
/usr/bin/python3 - "$out" <<'PY' || fail "demo metrics"
import json, sys
out = sys.argv[1]
a = json.load(open(f"{out}/demo/site_A/metrics.json"))
b = json.load(open(f"{out}/demo/site_B/metrics.json"))
print(f"site A: {a['inputs']}, captured {a['frames']['captured']}, portraits sent {a['frames']['portraits_sent']}; "
      f"site B displayed {b['frames']['displayed']}")
assert a["inputs"] == f"replay of {out}/recordings", a["inputs"]
assert a["frames"]["captured"] >= 1 and a["frames"]["portraits_sent"] >= 1
assert b["frames"]["displayed"] >= 1
PY
echo "k4a recordings played as a site's cameras: ok"
