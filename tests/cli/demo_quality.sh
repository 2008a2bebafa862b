#!/usr/bin/env bash
# `demo --quality fast` and `--quality best` run, and their metrics say which options were used:
# the demo's own metrics.json and each site's name the preset, and each site ran with its knobs.
set -euo pipefail
binary=$1 out=$2
presets=$(dirname "$0")/../../assets/quality/presets.json
for preset in fast best; do
  rm -rf "$out-$preset"
  # A low camera resolution over the preset's own keeps the test short.
  "$binary" demo --quality "$preset" --frames 2 --width 96 --height 54 --resolution-scale 0.1 --out "$out-$preset"
  preset_of() { /usr/bin/python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['quality']['preset'])" "$1"; }
  [ "$(preset_of "$out-$preset/metrics.json")" = "$preset" ] || { echo "demo metrics.json does not name the preset $preset" >&2; exit 1; }
  views=$(/usr/bin/python3 -c "import json,sys; p=json.load(open(sys.argv[1]))['presets'][sys.argv[2]]; print(p.get('ibr', {}).get('views', 4))" "$presets" "$preset")
  for site in A B; do
    metrics="$out-$preset/site_$site/metrics.json"
    [ "$(preset_of "$metrics")" = "$preset" ] || { echo "site $site: metrics.json does not name the preset $preset" >&2; exit 1; }
    tr -d ' \n' < "$metrics" | grep -q "\"ibr\":{[^}]*\"views\":$views" ||
      { echo "site $site: not the preset's $views views" >&2; exit 1; }
  done
done
echo "demo --quality ok"
