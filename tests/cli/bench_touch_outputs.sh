#!/usr/bin/env bash
# `bench touch`: its figures printed and in bench_touch.json, and what they must show.
#   bench_touch_outputs.sh BINARY OUT
set -euo pipefail
binary=$1 out=$2
rm -rf "$out"
"$binary" bench touch --frames 50 --out "$out" | tee "$out.log"
grep -Eq "^  without prediction +median [+-][0-9.]+ ms, \|error\| 90th percentile [0-9.]+ ms" "$out.log"
grep -Eq "^  with prediction +median [+-][0-9.]+ ms, \|error\| 90th percentile [0-9.]+ ms" "$out.log"
/usr/bin/python3 - "$out/bench_touch.json" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
without, with_ = r["without_prediction"], r["with_prediction"]
assert r["claps"] == 50
for mode in (without, with_):
    assert mode["claps_felt"] == 50 and mode["claps_not_felt"] == 0, mode
    assert mode["false_pulses"] == 0, mode  # no miss, graze or hover vibrates
# Without prediction the vibration comes after the contact by the motor's spin-up and more.
assert without["contact_to_vibration_ms"]["median"] > 60, without
assert without["pulses"]["predicted"] == 0
# With it: centred on the contact, and its 90th percentile under half of the one without.
e = with_["contact_to_vibration_ms"]
assert abs(e["median"]) < 10 and e["abs_p90"] < 0.5 * without["contact_to_vibration_ms"]["abs_p90"], e
assert with_["pulses"]["confirmed"] >= 45, with_["pulses"]
print("bench touch: p90 |error|", without["contact_to_vibration_ms"]["abs_p90"], "->", e["abs_p90"], "ms")
PY
