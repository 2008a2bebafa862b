#!/usr/bin/env bash
# `record --tracker leap:URL` as a user runs it: two live devices through the fake libk4a.so.1.4
# (paced as devices are) and a fake Leap service serving the clap's hands. The folder gets a
# tracker.jsonl whose frames lie on the cameras' device clock, among the captures' times, and it
# replays as site A with its hands ("the recording's tracker.jsonl"). A service that does not
# answer is refused before any camera starts, and leaves no folder behind.
#   record_with_hands.sh BINARY OUT FAKE_LIBRARY FAKE_SERVICE SCENE DEVICES_DIR
set -euo pipefail
source "$(dirname "$0")/listening.sh"
binary=$1 out=$2 fake=$3 service=$4 scene=$5 devices=$6
rm -rf "$out"
mkdir -p "$out"
fail() { echo "FAIL: $*" >&2; exit 1; }
export REMOTETOUCH_K4A_LIBRARY=$fake REMOTETOUCH_FAKE_K4A_PACED=1 REMOTETOUCH_FAKE_K4A_LOOPS=12
export REMOTETOUCH_FAKE_K4A_RECORDINGS=$devices/top-left.mkv:$devices/top-centre.mkv

"$service" "$scene" A 60 > "$out/service.out" 2> "$out/service.err" &
service_pid=$!
trap 'kill $service_pid 2> /dev/null || true' EXIT
leap_port=$(listening_port "$out/service.out" "$service_pid")
[ -n "$leap_port" ] || fail "the fake Leap service never listened"

"$binary" record --site "$devices/live.json" --seconds 20 --tracker "leap:ws://127.0.0.1:$leap_port/v6.json" \
  --out "$out/recorded" > "$out/record.out" 2>&1 || { cat "$out/record.out"; fail "record failed"; }
cat "$out/record.out"
grep -Eq "record: [1-9][0-9]* tracker frames \([1-9][0-9]* with hands" "$out/record.out" || fail "no tracker frames recorded"
[ ! -e "$out/recorded/tracker.arrivals.jsonl" ] || fail "the arrivals file was left behind"
"$binary" inspect-camera "$out/recorded/top-left.mkv" --frames 1 --out "$out/inspect" > /dev/null 2>&1 ||
  fail "inspect-camera could not read the recording"
/usr/bin/python3 - "$out" <<'PY' || fail "the tracker frames are not on the cameras' clock"
import json, sys
out = sys.argv[1]
first = json.load(open(f"{out}/inspect/camera.json"))["captures"][0]["color_device_us"]
# 12 passes of 5 captures at 30 frames a second: the cameras ran for 2 s of their clock.
last = first + 12 * 5 * 1e6 / 30
times = [json.loads(line)["timestamp"] for line in open(f"{out}/recorded/tracker.jsonl") if line.strip()]
assert all(b > a for a, b in zip(times, times[1:])), "tracker times do not increase"
within = [t for t in times if first <= t <= last]
print(f"captures {first}..{last:.0f} us; {len(times)} tracker frames {times[0]}..{times[-1]} us, {len(within)} among the captures")
# The service sends 50 frames a second: those sent while the cameras ran lie among their captures.
assert len(within) >= 0.8 * 50 * (last - first) / 1e6, "too few tracker frames among the captures"
assert times[0] > first - 1e6 and times[-1] < last + 0.5e6, "tracker frames far from the captures"
PY

"$binary" demo --scene "$scene" --replay-a "$out/recorded" --views 2 --frames 5 --width 64 --height 36 \
  --display headless --out "$out/demo" > "$out/demo.out" 2> "$out/demo.err" || { cat "$out/demo.err"; fail "the replay failed"; }
/usr/bin/python3 - "$out" <<'PY' || fail "the replay's metrics"
import json, sys
a = json.load(open(f"{sys.argv[1]}/demo/site_A/metrics.json"))
print(f"replay: tracker {a['tracker']['source']}, portraits sent {a['frames']['portraits_sent']}")
assert a["tracker"]["source"] == "the recording's tracker.jsonl", a["tracker"]
PY

set +e
"$binary" record --site "$devices/live.json" --seconds 1 --tracker "leap:ws://127.0.0.1:9/v6.json" \
  --out "$out/no-service" > "$out/no-service.out" 2>&1
status=$?
set -e
[ "$status" -ne 0 ] || fail "record without a Leap service succeeded"
grep -q "ws://127.0.0.1:9/v6.json" "$out/no-service.out" || { cat "$out/no-service.out"; fail "the error does not name the service"; }
[ ! -e "$out/no-service/site.json" ] || fail "record without a Leap service wrote a site"
echo "recorded with hands"
