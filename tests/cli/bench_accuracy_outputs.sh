#!/usr/bin/env bash
# `remotetouch bench accuracy` as a user runs it, on the tiny grid: one row per configuration, the
# plot and a front that holds (tests/cli/check_accuracy.py), progress with the time left, a
# stopped run resumed, a run measured otherwise refused, and --budget-ms and --quality choosing a
# configuration that the metrics then name.
set -euo pipefail
binary=$1 out=$2
here=$(dirname "$0")
rm -rf "$out" "$out"-*
run=(bench accuracy --grid tiny --scenes wave --frames 2 --width 96 --height 54 --out "$out" --validation)
"$binary" "${run[@]}" | tee "$out.log"
/usr/bin/python3 "$here/check_accuracy.py" "$out" 7
grep -Eq '^\[7/7\] .*GPU ms .*so far, about [0-9]+s left$' "$out.log" || { echo "no progress with the time left" >&2; exit 1; }
grep -q '^Command: `remotetouch bench accuracy --scenes wave --grid tiny' "$out/pareto.md" || { echo "pareto.md lacks the command" >&2; exit 1; }

# A run stopped after six configurations: the seventh alone is measured again.
head -n 7 "$out/results.csv" > "$out/results.trimmed" && mv "$out/results.trimmed" "$out/results.csv"
"$binary" "${run[@]}" | tee "$out-resumed.log"
grep -q '7 configurations (6 already in' "$out-resumed.log" || { echo "the resumed run did not skip six" >&2; exit 1; }
[ "$(grep -c '^\[1/1\]' "$out-resumed.log")" = 1 ] || { echo "the resumed run did not measure exactly one" >&2; exit 1; }
/usr/bin/python3 "$here/check_accuracy.py" "$out" 7

# Other frames in the same folder would mix measurements: refused, saying how to go on.
if "$binary" bench accuracy --grid tiny --scenes wave --frames 3 --width 96 --height 54 --out "$out" > "$out-other.log" 2>&1; then
  echo "a run with other frames was resumed" >&2; exit 1
fi
grep -q 'holds results measured otherwise.*give the same scenes, frames, size and device to resume, or another --out' \
  "$out-other.log" || { echo "no clear error for a mismatched resume" >&2; cat "$out-other.log" >&2; exit 1; }

# --budget-ms: the most accurate configuration within the budget, named in the metrics.
"$binary" eval ibr --scene wave --frames 1 --width 96 --height 54 --budget-ms 100000 --budget-results "$out/results.csv" \
  --out "$out-budget" --validation > "$out-budget.log"
best=$(/usr/bin/python3 -c "import csv,sys; rows=list(csv.DictReader(open(sys.argv[1]))); print(max(rows, key=lambda r: float(r['psnr_fg_db']))['options'])" "$out/results.csv")
tr -d '\n' < "$out-budget/metrics.json" | grep -q "\"options\": \"$best\"" || { echo "--budget-ms did not choose '$best'" >&2; exit 1; }
grep -q '"budget_ms": 100000' "$out-budget/metrics.json" || { echo "metrics.json lacks the budget" >&2; exit 1; }
if "$binary" eval ibr --scene wave --frames 1 --width 96 --height 54 --budget-ms 0.001 --budget-results "$out/results.csv" \
  --out "$out-tight" > "$out-tight.log" 2>&1; then
  echo "an impossible budget was accepted" >&2; exit 1
fi
grep -q 'nothing measured at 96x54 fits 0.001 GPU ms a frame; the fastest' "$out-tight.log" || { echo "no clear error for the budget" >&2; exit 1; }

# --quality: the preset's options, named in the metrics, under the options given.
"$binary" eval ibr --scene wave --frames 1 --width 96 --height 54 --quality best --refine 3 --out "$out-best" --validation > /dev/null
[ "$(/usr/bin/python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['quality']['preset'])" "$out-best/metrics.json")" = best ] ||
  { echo "metrics.json does not name the preset" >&2; exit 1; }
grep -q '"refine_hypotheses": 3' "$out-best/metrics.json" || { echo "--refine 3 did not apply over the preset" >&2; exit 1; }
echo "bench accuracy outputs ok"
