#!/usr/bin/env bash
# A site whose hands come from the Leap service live (`site --tracker leap:URL`), here a fake
# service serving the clap's tracker frames: site A reads them while it plays a short clap against
# a simulated site B; its metrics name the service and count the frames, with hands, in the site
# frame (the touch loop and the peer get them as skeletons).
#   session_leap.sh BINARY FAKE_SERVICE SCENE_FILE OUT
set -euo pipefail
source "$(dirname "$0")/listening.sh"
binary=$1 service=$2 scene=$3 out=$4
rm -rf "$out"
mkdir -p "$out"
fail() { echo "FAIL: $*" >&2; exit 1; }
# A random key: a hand-made one (a padded number) is refused as too regular to be a secret.
head -c 32 /dev/urandom | od -An -v -tx1 | tr -d ' \n' > "$out/session.key"
chmod 600 "$out/session.key"
common=(--width 96 --height 54 --resolution-scale 0.1 --time-scale 1 --connect-timeout 60 --key-file "$out/session.key")

"$service" "$scene" A 120 > "$out/service.out" 2> "$out/service.err" &
service_pid=$!
trap 'kill $service_pid 2> /dev/null || true' EXIT
leap_port=$(listening_port "$out/service.out" "$service_pid")
[ -n "$leap_port" ] || fail "the fake Leap service never listened"

"$binary" site --site A --scene clap --frames 60 --listen 127.0.0.1:0 --tracker "leap:ws://127.0.0.1:$leap_port/v6.json" \
  "${common[@]}" --out "$out/A" > "$out/a.out" 2> "$out/a.err" &
a=$!
port=$(listening_port "$out/a.out" "$a")
[ -n "$port" ] || { cat "$out/a.err" >&2; kill "$a"; fail "site A never listened"; }
set +e
"$binary" site --site B --scene clap --frames 60 --peer "127.0.0.1:$port" "${common[@]}" --out "$out/B" > "$out/b.out" 2> "$out/b.err"
b_status=$?
wait "$a"
a_status=$?
set -e
cat "$out/a.err" "$out/b.err"
[ "$a_status" -eq 0 ] || fail "site A exited with $a_status"
[ "$b_status" -eq 0 ] || fail "site B exited with $b_status"
grep -q "tracker: the Leap service at ws://127.0.0.1:$leap_port/v6.json" "$out/a.err" || fail "site A does not name its tracker"
/usr/bin/python3 - "$out/A/metrics.json" "$out/B/metrics.json" "$leap_port" <<'PY' || fail "tracker metrics"
import json, sys
a, b, port = json.load(open(sys.argv[1])), json.load(open(sys.argv[2])), sys.argv[3]
t = a["tracker"]
print("site A tracker:", json.dumps(t))
assert t["source"] == f"the Leap service at ws://127.0.0.1:{port}/v6.json"
assert t["connections"] == 1 and t["state"] == "connected"
assert t["service_version"] == "fake-4.1.0"
assert t["frames"] >= 50 and t["frames_with_hands"] >= 20, "too few live frames"
assert t["messages_refused"] == {"malformed": 0, "oversized": 0}
assert 40 <= t["frames_per_second"] <= 60, "the service sends 50 frames a second"
assert b["tracker"]["source"] == "simulated from the scene"
PY
echo "site A's hands came from the Leap service"
