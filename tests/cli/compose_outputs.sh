#!/usr/bin/env bash
# `remotetouch compose` as a user runs it, small: frames, pass dumps, metrics and the profile.
set -euo pipefail
binary=$1 out=$2
rm -rf "$out"
mkdir -p "$out"
"$binary" compose --frames 4 --width 97 --height 61 --out "$out" --dump-passes --profile --validation | tee "$out/log.txt"
for f in frame_0000.png frame_0003.png metrics.json passes/hand_alpha.hand_alpha.exr passes/overlay.fused.png \
         passes/composite.display.png; do
  [ -s "$out/$f" ] || { echo "missing $out/$f" >&2; exit 1; }
done
grep -q "median ms" "$out/log.txt"
grep -q '"hand_alpha"' "$out/metrics.json"
echo "compose outputs ok"
