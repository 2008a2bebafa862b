#!/usr/bin/env bash
# Two sites started by hand as the README shows them, with the defaults a new user gets: each
# site's output folder names the site, a second run in a live run's folder is refused, the time
# scale follows the device, each site ends with its table; one site ending ends the other's
# session; an unreachable peer, or one whose name does not resolve, is reported once, with the
# reason, within the connect timeout counted from the start.
#   session_by_hand.sh BINARY OUT
set -euo pipefail
source "$(dirname "$0")/listening.sh"
binary=$1 out=$2
rm -rf "$out"
mkdir -p "$out"
cd "$out"  # the default output folders are relative to where the sites run
fail() {
  echo "FAIL: $*" >&2
  for f in *.err; do echo "== $f" >&2; cat "$f" >&2; done
  exit 1
}
small=(--scene clap --width 64 --height 36 --resolution-scale 0.05 --motor simulated --display headless)
"$binary" keygen session.key > /dev/null

# 1. Both sites on their defaults.
"$binary" site --site A --listen 127.0.0.1:0 --key-file session.key --frames 12 "${small[@]}" > a.out 2> a.err &
a=$!
port=$(listening_port a.out)
[ -n "$port" ] || fail "site A never listened"
set +e
"$binary" site --site A --listen 127.0.0.1:0 --key-file session.key --frames 12 "${small[@]}" > a2.out 2> a2.err
a2_status=$?
set -e
[ "$a2_status" -eq 1 ] || fail "a second site A in out/site_A exited with $a2_status, expected 1"
grep -q "output folder out/site_A is in use by another running process (pid $a): give this one its own --out" a2.err ||
  fail "the second site A did not say that its folder is in use"
"$binary" site --site B --peer "127.0.0.1:$port" --key-file session.key --frames 12 "${small[@]}" > b.out 2> b.err ||
  fail "site B failed"
wait "$a" || fail "site A failed"
for site in A B; do
  out_lower=$(echo "$site" | tr AB ab)
  [ -f "out/site_$site/metrics.json" ] || fail "no out/site_$site/metrics.json"
  grep -q "^frames displayed" "$out_lower.out" || fail "site $site printed no closing table"
  grep -q "^progress" "$out_lower.out" && fail "site $site printed the demo's progress lines"
  grep -Eq "site $site: time scale (0.25 \(a quarter of real time: .* is a CPU Vulkan driver\)|1 \(real time\)); --time-scale sets it" \
    "$out_lower.err" || fail "site $site did not say which time scale it chose"
  grep -q "site $site: written to out/site_$site: events.jsonl, metrics.json" "$out_lower.err" || fail "site $site did not say where it wrote"
done
/usr/bin/python3 - <<'PY' || fail "the sites' metrics"
import json
for site in "AB":
    m = json.load(open(f"out/site_{site}/metrics.json"))
    cpu = "llvmpipe" in m["device"] or "lavapipe" in m["device"]
    assert m["time_scale"] == (0.25 if cpu else 1.0), (site, m["device"], m["time_scale"])
    assert m["connected"] is True and m["frames"]["displayed"] > 0, site
print("two sites by hand: both displayed frames, time scale", m["time_scale"], "on", m["device"])
PY

# 2. Site A stops (SIGTERM) while B's scene has long to run: B ends its session too, normally
# and at once, instead of reconnecting until its own scene is over.
rm -rf out
"$binary" site --site A --listen 127.0.0.1:0 --key-file session.key --frames 150 "${small[@]}" > a.out 2> a.err &
a=$!
port=$(listening_port a.out)
[ -n "$port" ] || fail "site A never listened (second run)"
"$binary" site --site B --peer "127.0.0.1:$port" --key-file session.key --frames 150 "${small[@]}" > b.out 2> b.err &
b=$!
for _ in $(seq 1 600); do grep -q "^connected" b.out && break; sleep 0.1; done
grep -q "^connected" b.out || fail "the sites never connected (second run)"
kill -TERM "$a"
set +e
wait "$a"
wait "$b"
b_status=$?
set -e
[ "$b_status" -eq 0 ] || fail "site B exited with $b_status after site A ended, expected 0"
grep -q "site B: the other site ended the session: stopping" b.err || fail "site B did not say why it stopped"
grep -q "reconnect\|connect to" b.err && fail "site B tried to reconnect to a site that ended its session"
/usr/bin/python3 - <<'PY' || fail "site B's metrics after its peer ended"
import json
m = json.load(open("out/site_B/metrics.json"))
assert m["stopped_by"] == "peer", m["stopped_by"]
assert m["net"]["connections_lost"] == 0 and m["net"]["reconnects"] == 0, m["net"]
# The scene would have lasted 150 frames at 30 fps over the time scale: B stopped well before.
scene_s = 150 / 30 / m["time_scale"]
assert m["elapsed_s"] < scene_s / 2, (m["elapsed_s"], scene_s)
print("site B ended with its peer after", round(m["elapsed_s"], 1), "s of a", scene_s, "s scene")
PY

# 3. Nobody at the peer's port: one line with the reason, the end within the connect timeout
# counted from the site's start.
start=$(date +%s%N)
set +e
"$binary" site --site B --peer "127.0.0.1:$port" --key-file session.key --connect-timeout 3 --out lonely "${small[@]}" \
  > lonely.out 2> lonely.err
lonely_status=$?
set -e
elapsed_ms=$(( ($(date +%s%N) - start) / 1000000 ))
[ "$lonely_status" -eq 2 ] || fail "a site with no peer exited with $lonely_status, expected 2"
[ "$(grep -c "connect to 127.0.0.1:$port failed: Connection refused" lonely.err)" -eq 2 ] ||
  fail "the unreachable peer was not reported once, with the reason, and in the final message"
grep -q "no connection to the other site within 3 s of the start" lonely.err || fail "no final message"
# The wait counts from the start (the search for the eyes before the call included): the end
# comes within a second of the timeout.
[ "$elapsed_ms" -lt 4000 ] || fail "a 3-s connect timeout ended after $elapsed_ms ms"

# 4. A peer's name that does not resolve: once, with the reason. In a network namespace of its
# own with no way out, so that the lookup fails here and nothing leaves this machine.
if unshare -n true 2> /dev/null; then
  set +e
  unshare -n "$binary" site --site B --peer no-such-host.invalid:7000 --key-file session.key --connect-timeout 2 \
    --out unresolved "${small[@]}" > unresolved.out 2> unresolved.err
  unresolved_status=$?
  set -e
  [ "$unresolved_status" -eq 2 ] || fail "a site whose peer does not resolve exited with $unresolved_status, expected 2"
  [ "$(grep -c "cannot resolve no-such-host.invalid: ." unresolved.err)" -eq 2 ] ||
    fail "the unresolvable peer was not reported once, with the reason, and in the final message"
else
  echo "not checked: a peer's name that does not resolve (no network namespace here: unshare -n needs root)"
fi
echo "two sites by hand: defaults, the end of a peer and an unreachable peer hold"
