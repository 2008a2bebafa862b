#!/usr/bin/env bash
# `demo` forwards the image-based-model and hand options to both sites: each site's metrics.json
# records the settings it ran with under "ibr" and "hand" (pipeline::ibr_settings_json,
# hand_settings_json).
set -euo pipefail
binary=$1 out=$2
rm -rf "$out"
"$binary" demo --refine 9 --hand-shape-adaption off --frames 2 --width 96 --height 54 --resolution-scale 0.1 --out "$out"
for site in A B; do
  metrics="$out/site_$site/metrics.json"
  [ -s "$metrics" ] || { echo "missing $metrics" >&2; exit 1; }
  tr -d ' \n' < "$metrics" | grep -q '"ibr":{[^}]*"refine":9' || { echo "site $site: metrics.json does not say refine 9" >&2; exit 1; }
  tr -d ' \n' < "$metrics" | grep -q '"hand":{[^}]*"shape_adaption":"off"' || { echo "site $site: hand options not recorded" >&2; exit 1; }
done
