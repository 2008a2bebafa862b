#!/usr/bin/env bash
# `eval dual --tracker-latency 100`, small: the hand held at the newest skeleton the receiver has
# (dual) against the hand carried forward to the display time (dual_predicted).
#   eval_dual_prediction.sh BINARY OUT
set -euo pipefail
binary=$1 out=$2
rm -rf "$out"
"$binary" eval dual --scene clap --frame-step 10 --width 96 --height 54 --tracker-latency 100 \
  --variants dual,dual_predicted --no-plots --out "$out" | tee "$out.log"
/usr/bin/python3 - "$out/metrics.json" <<'PY'
import json, sys
m = json.load(open(sys.argv[1]))
assert m["tracker_latency_ms"] == 100 and m["variants"] == ["dual", "dual_predicted"], m["variants"]
for user in "AB":
    prediction = m["users"][user]["prediction"]
    assert prediction["frames"] > 0 and prediction["joints_behind_glass"] == 0, prediction
    assert 100 <= prediction["mean_skeleton_to_display_ms"] <= 120, prediction
    phases = m["users"][user]["phases"]
    held, predicted = phases["approach"]["dual"], phases["approach"]["dual_predicted"]
    print(f"user {user}: approach tip_err_px {held['tip_err_px']:.3f} -> {predicted['tip_err_px']:.3f}")
    # The reach is where it was a tenth of a second ago without prediction.
    assert predicted["tip_err_px"] <= 0.5 * held["tip_err_px"], (held, predicted)
    assert predicted["iou_hand_arm"] >= held["iou_hand_arm"] - 0.005, (held, predicted)
PY
