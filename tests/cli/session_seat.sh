#!/usr/bin/env bash
# A scene that asks for the seat ("viewpoint": "seat"): both sites send the seat's head position
# from the start, without a search, say so, and still measure it against the true eye.
set -euo pipefail
binary=$1 out=$2 scene=$3
rm -rf "$out"
"$binary" demo --scene "$scene" --frames 20 --width 96 --height 54 --resolution-scale 0.5 --time-scale 1 \
  --out "$out" >"$out.log" 2>&1 || { cat "$out.log"; echo "FAIL: demo exit status $?"; exit 1; }
/usr/bin/python3 - "$out" <<'PY'
import json, sys
m = json.load(open(f"{sys.argv[1]}/metrics.json"))
for site in "AB":
    v = m["sites"][site]["viewpoint"]
    print(f"site {site}: {v['describe']}; error against the true eye {v['error_against_true_eye']}")
    assert v["source"] == "seat" and v["describe"] == "seat (the scene asks for the seat)", v
    assert v["scene_asks_for"] == "seat" and v["frames_examined"] == 0, v
    assert v["position_m"] == [0.0, 0.1, 0.7], v["position_m"]
    # The seat's head centre is ~9 cm behind the face's eyes: the error says so.
    assert 80 < v["error_against_true_eye"]["first_frame_mm"] < 120, v["error_against_true_eye"]
PY
grep -q "site A: eye: seat (the scene asks for the seat)" "$out.log" || { echo "FAIL: the log does not say the seat stands"; exit 1; }
echo "seat viewpoint ok"
