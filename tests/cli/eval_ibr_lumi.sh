#!/usr/bin/env bash
# `remotetouch eval ibr --blend lumi` as a user runs it, tiny: Lumi-Net's passes run in place of
# the lumigraph blending, every figure is finite, and the metrics and the first lines say which
# blend ran; a weights file that is not there is a clear error naming it.
set -euo pipefail
binary=$1 out=$2
rm -rf "$out"
"$binary" eval ibr --scene wave --frames 2 --width 41 --height 23 --supersample 1 --blend lumi --out "$out" --validation \
  | tee "$out.log"
grep -q '^blend: lumi (.*lumi_net.bin, C = 16, 2 blocks, at 1/2)' "$out.log" || { echo "the blend is not printed" >&2; exit 1; }
grep -q 'lumi_conv_in' "$out.log" && grep -q 'lumi_blend' "$out.log" || { echo "no Lumi-Net pass timed" >&2; exit 1; }
if grep -q '^ibr_blend ' "$out.log"; then echo "the lumigraph blending ran too" >&2; exit 1; fi
python3 - "$out/metrics.json" <<'PY'
import json, math, sys
m = json.load(open(sys.argv[1]))
assert m["blend"] == "lumi" and m["ibr"]["blend"] == "lumi", "metrics do not name the blend"
assert m["ibr"]["lumi_weights"].endswith("lumi_net.bin")
for key in ("psnr_fg_db", "psnr_hand_db", "alpha_iou", "depth_mae_edge_mm"):
    assert isinstance(m[key], (int, float)) and math.isfinite(m[key]), f"{key} is {m[key]}"
assert all(math.isfinite(v) for v in m["frame_psnr_fg_db"]), "a frame's PSNR is not finite"
PY
# ULR is the default, and says so.
"$binary" eval ibr --scene wave --frames 1 --width 41 --height 23 --supersample 1 --out "$out-ulr" | tee "$out-ulr.log"
grep -q '^blend: ulr (k = 3)' "$out-ulr.log" && grep -q '"blend": "ulr"' "$out-ulr/metrics.json" \
  || { echo "the default blend is not ulr" >&2; exit 1; }
# A weights file that is not there.
if "$binary" eval ibr --frames 1 --width 41 --height 23 --blend lumi --lumi-weights "$out-no-such.bin" \
  --out "$out-missing" > "$out-missing.log" 2>&1; then
  echo "a missing weights file was accepted" >&2; exit 1
fi
grep -q "remotetouch: error: .*no-such.bin" "$out-missing.log" || { cat "$out-missing.log" >&2; echo "no clear error" >&2; exit 1; }
echo "eval ibr --blend lumi ok"
