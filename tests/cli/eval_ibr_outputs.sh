#!/usr/bin/env bash
# `remotetouch eval ibr` as a user runs it, small: both fusions, the metrics file with every
# figure the issue asks for, portraits and error images, and the table.
set -euo pipefail
binary=$1 out=$2
rm -rf "$out"
"$binary" eval ibr --scene wave --frames 2 --fusion both --width 81 --height 45 --out "$out" --validation | tee "$out.log"
[ -s "$out/metrics.json" ] || { echo "missing $out/metrics.json" >&2; exit 1; }
for key in psnr_fg_db psnr_hand_db depth_mae_edge_mm alpha_iou gpu_ms by_fusion fg_error_by_region interior; do
  grep -q "\"$key\"" "$out/metrics.json" || { echo "metrics.json lacks $key" >&2; exit 1; }
done
# Every figure is a number (null would mean an empty region: not expected on wave).
if grep -Eq '"(psnr_fg_db|psnr_hand_db|depth_mae_edge_mm|alpha_iou)": null' "$out/metrics.json"; then
  echo "a metric is null" >&2
  exit 1
fi
# Each fusion's figures in a range around what the code measures on lavapipe (psnr_fg 16.6 and
# 16.5 dB, psnr_hand 20.6, depth_mae_edge 3.1 and 2.8 mm, alpha_iou 0.963 and 0.960, bias -2.5
# and -1.7 mm), 0.5 dB, 0.01 and 2 to 2.5 mm wide of it: one of the four views never sampled gives
# 15.9 dB, 19.97 dB and 0.945, depths read 1 % too far an edge error of 7.5 and 9.4 mm: both
# fall out; a truth compared with itself would too, above.
/usr/bin/python3 - "$out/metrics.json" <<'PY'
import json, sys
m = json.load(open(sys.argv[1]))
ranges = {"psnr_fg_db": (16.0, 25.0), "psnr_hand_db": (20.0, 30.0), "depth_mae_edge_mm": (0.5, 5.0),
          "alpha_iou": (0.95, 0.999), "depth_bias_mm": (-5.0, 5.0)}
assert sorted(m["by_fusion"]) == ["avg", "min"], list(m["by_fusion"])
for fusion, figures in m["by_fusion"].items():
    for key, (low, high) in ranges.items():
        assert low <= figures[key] <= high, f"{fusion} {key} = {figures[key]}, expected in [{low}, {high}]"
PY
for f in 0000_truth.png 0000_min_portrait.png 0000_avg_portrait.png 0001_min_color_error_x4.png \
         0001_avg_depth_error_per_50mm.png; do
  [ -s "$out/images/$f" ] || { echo "missing $out/images/$f" >&2; exit 1; }
done
grep -Eq '^min +[0-9.]+' "$out.log" && grep -Eq '^avg +[0-9.]+' "$out.log"
# Each frame's own PSNR (two frames) and the worst frames printed.
grep -Eq '"frame_psnr_fg_db": \[$' "$out/metrics.json" || { echo "metrics.json lacks frame_psnr_fg_db" >&2; exit 1; }
grep -Eq '^\[min\]  000[01] [0-9.]+  000[01] [0-9.]+$' "$out.log" || { echo "no worst frames printed" >&2; exit 1; }
# A fixed selection by camera name is used and recorded.
"$binary" eval ibr --scene wave --frames 1 --width 41 --height 23 --cameras top-centre,bottom-right \
  --edge-inset 0.3 --out "$out-cameras" --validation | tee "$out-cameras.log"
grep -q "2 of 6 cameras" "$out-cameras.log" && grep -q 'cameras fixed: top-centre, bottom-right' "$out-cameras.log" || { echo "fixed cameras not printed" >&2; exit 1; }
grep -q '"views": 2' "$out-cameras/metrics.json" || { echo "fixed cameras: not 2 views" >&2; exit 1; }
grep -q '"bottom-right"' "$out-cameras/metrics.json" || { echo "fixed cameras not recorded" >&2; exit 1; }
grep -q '"edge_inset_depth_px": 0.3' "$out-cameras/metrics.json" || { echo "edge inset not recorded" >&2; exit 1; }
# A supersampled portrait at the site's own camera resolution: the resolve pass runs and is timed.
"$binary" eval ibr --scene wave --frames 1 --width 41 --height 23 --portrait-supersample 2 --resolution-scale 0.25 \
  --out "$out-supersampled" --validation | tee "$out-supersampled.log"
grep -q '"portrait_supersampling": 2' "$out-supersampled/metrics.json" || { echo "no portrait_supersampling" >&2; exit 1; }
grep -q 'ibr_resolve' "$out-supersampled.log" || { echo "no ibr_resolve timing" >&2; exit 1; }
# Carving and refinement, every third frame from frame 4, k = 4, the last frame's passes dumped.
"$binary" eval ibr --scene wave --width 41 --height 23 --carve --refine 3 --best-views 4 --first-frame 4 --frame-step 3 \
  --frames 2 --dump-passes --out "$out-carved" --validation | tee "$out-carved.log"
grep -q 'ibr_carve' "$out-carved.log" || { echo "no ibr_carve timing" >&2; exit 1; }
grep -q '"see_through_carving": true' "$out-carved/metrics.json" || { echo "carving not recorded" >&2; exit 1; }
grep -q '"best_views": 4' "$out-carved/metrics.json" || { echo "best views not recorded" >&2; exit 1; }
tr -d ' \n' < "$out-carved/metrics.json" | grep -q '"scene_frames":\[4,7\]' || { echo "scene frames not 4, 7" >&2; exit 1; }
[ -s "$out-carved/images/0007_min_portrait.png" ] || { echo "frame 7 not written" >&2; exit 1; }
[ -s "$out-carved/passes/min/ibr_carve.ibr_carved_depth.exr" ] || { echo "carve pass not dumped" >&2; exit 1; }
# A first frame past the scene's end is refused, naming the option.
if "$binary" eval ibr --scene wave --first-frame 100000 --out "$out-past" > "$out-past.log" 2>&1; then
  echo "a first frame past the end was accepted" >&2; exit 1
fi
grep -q -- '--first-frame 100000 is past' "$out-past.log" || { echo "no clear error for --first-frame" >&2; exit 1; }
echo "eval ibr outputs ok"
