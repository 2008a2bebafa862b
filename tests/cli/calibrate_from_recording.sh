#!/usr/bin/env bash
# `calibrate extrinsics --views-from` as a user runs it on a real installation, with the cameras
# simulated: `calibrate synthesize --board-recording` records the chessboard held in front of the
# screen as k4a recordings of the six cameras, and the site is calibrated from them with the
# devices' factory lenses; the cameras must land where the truth has them, within what the 1 mm
# tape-measured distances allow. A folder that is no recording is refused, naming it.
#   calibrate_from_recording.sh BINARY OUT ASSETS
set -euo pipefail
binary=$1 out=$2 assets=$3
rm -rf "$out"
mkdir -p "$out"
fail() { echo "FAIL: $*" >&2; exit 1; }

"$binary" calibrate synthesize --out "$out/synthetic" --board-recording > "$out/synthesize.out"
cp "$assets/sites/default.json" "$out/site.json"
"$binary" calibrate extrinsics --input "$out/synthetic/extrinsics_from_recording.json" \
  --views-from "$out/synthetic/board_recording" --site "$out/site.json" > "$out/calibrate.out"
cat "$out/calibrate.out"
grep -q "the board was found in 24 of 24 frame sets searched" "$out/calibrate.out" || fail "not every view was found"
grep -q "updated $out/site.json (6 cameras" "$out/calibrate.out" || fail "the site file was not updated"

/usr/bin/python3 - "$out/synthetic/truth_site.json" "$out/site.json" <<'PY' || fail "the cameras are not where the truth has them"
import json, math, sys
def pose(camera):
    m = camera["camera_from_site"]
    rows = [m[i * 4:(i + 1) * 4] for i in range(4)] if len(m) == 16 else m
    rotation = [row[:3] for row in rows[:3]]
    position = [-sum(rotation[j][i] * rows[j][3] for j in range(3)) for i in range(3)]
    return rotation, position
truth = {c["name"]: pose(c) for c in json.load(open(sys.argv[1]))["cameras"]}
found = {c["name"]: pose(c) for c in json.load(open(sys.argv[2]))["cameras"]}
for name, (rotation, position) in truth.items():
    found_rotation, found_position = found[name]
    off_mm = math.dist(position, found_position) * 1000
    trace = sum(sum(rotation[i][k] * found_rotation[i][k] for k in range(3)) for i in range(3))
    turned_deg = math.degrees(math.acos(max(-1.0, min(1.0, (trace - 1) / 2))))
    print(f"{name}: {off_mm:.2f} mm, {turned_deg:.3f} degrees from the truth")
    assert off_mm < 10.0 and turned_deg < 0.5, name
PY

if "$binary" calibrate extrinsics --input "$out/synthetic/extrinsics_from_recording.json" \
     --views-from "$out/synthetic/intrinsics" --site "$out/site.json" > "$out/refused.out" 2>&1; then
  fail "a folder with no recording was taken"
fi
grep -q "intrinsics" "$out/refused.out" || fail "the refusal does not name the folder: $(cat "$out/refused.out")"
echo "calibrated from the recording"
