#!/usr/bin/env bash
# Two sites meet in a Janus room and clap, neither listening for the other: a Janus started in
# the network namespace the test runs in (tests/cli/in_network_namespace.sh), both sites with
# --transport webrtc --janus --room --room-secret. Each must connect through the room, see the
# other's portraits, seal its data channels with the site key, and feel the clap once. A site
# given a wrong pin is refused with Janus's reason, and so is one that asks a Janus which makes
# rooms for its administrator only for a room that does not exist. Then the other site leaving
# and coming back: site B's scene ends and B starts again while A stays (its hand held at the
# glass); both must connect again through the room, with a new handshake, and the second clap
# must give a touch and a motor pulse at each site. Exits 77 (skipped) where there is no namespace
# or no Janus.
#   session_janus.sh BINARY OUT
set -euo pipefail
binary=$1 out=$2
if [ -z "${RT_TEST_NAMESPACE_ADDRESS:-}" ]; then echo "SKIPPED: not in a network namespace of the test's own"; exit 77; fi
if [ ! -x /usr/bin/janus ]; then echo "SKIPPED: /usr/bin/janus is missing: apt-get install janus"; exit 77; fi
rm -rf "$out"
mkdir -p "$out"
cd "$out"
fail() {
  echo "FAIL: $*" >&2
  for f in *.err; do echo "== $f" >&2; tail -30 "$f" >&2; done
  exit 1
}
"$RT_TEST_START_JANUS" "$PWD/janus" "$RT_TEST_NAMESPACE_ADDRESS" &
janus=$!
trap 'kill $janus 2>/dev/null; wait $janus 2>/dev/null || true' EXIT
for _ in $(seq 100); do
  (exec 3<>/dev/tcp/127.0.0.1/8188) 2>/dev/null && break
  sleep 0.1
done
"$binary" keygen session.key > /dev/null
echo "a pin of the room" > pin.txt
echo "another pin" > wrong_pin.txt
# Site A's user holds the hand at the glass long after the clap, so that site B's user, back
# after a restart, claps against it: the scene's clap with A's hold made long.
/usr/bin/python3 - "$(cd "$(dirname "$0")/../../assets" && pwd)" <<'PY'
import json, sys
assets = sys.argv[1]
scene = json.load(open(f"{assets}/scenes/clap.json"))
for site in scene["sites"].values():
    site["site"] = f"{assets}/sites/default.json"
scene["sites"]["A"]["motion"]["hold_s"] = 120.0
json.dump(scene, open("clap_held.json", "w"), indent=1)
PY
small=(--width 64 --height 36 --resolution-scale 0.05 --motor simulated --display headless
       --transport webrtc --janus ws://127.0.0.1:8188 --key-file session.key)
# Waits until a site's events say its clap is over (the touch ended), for up to 120 s.
wait_for_clap() {
  for _ in $(seq 1200); do
    grep -q '"event":"touch_end"' "$1/events.jsonl" 2>/dev/null && return 0
    kill -0 "$2" 2>/dev/null || return 1
    sleep 0.1
  done
  return 1
}
# A runs until the test stops it (a scene far longer than B's two runs), B for one clap each time.
"$binary" site --site A --scene clap_held.json --frames 3600 "${small[@]}" --room 7 --room-secret pin.txt --out site_A > a.out 2> a.err &
a=$! b=
trap 'kill $janus $a $b 2>/dev/null; wait $janus $a $b 2>/dev/null || true' EXIT
"$binary" site --site B --scene clap_held.json --frames 3600 "${small[@]}" --room 7 --room-secret pin.txt --out site_B > b.out 2> b.err &
b=$!
wait_for_clap site_B "$b" || fail "site B felt no clap"
# B's machine goes down: no goodbye to Janus, which sees its WebSocket close.
kill -KILL "$b"
wait "$b" 2>/dev/null || true
# B again, as after a restart: a new process, a new handshake, the same room. Stopped by its user
# once the clap is over.
b_again_started_ns=$(date +%s%N)
"$binary" site --site B --scene clap_held.json --frames 3600 "${small[@]}" --room 7 --room-secret pin.txt --out site_B_again > b2.out 2> b2.err &
b=$!
wait_for_clap site_B_again "$b" || fail "site B, started again, felt no clap"
echo "site B started again: its clap over $(( ($(date +%s%N) - b_again_started_ns) / 1000000 )) ms after its start"
# Waits until FOLDER's events hold N of EVENT, for up to 60 s.
wait_for_events() {
  for _ in $(seq 600); do
    [ "$(grep -c "\"event\":\"$2\"" "$1/events.jsonl" 2>/dev/null)" -ge "$3" ] && return 0
    sleep 0.1
  done
  return 1
}
# Janus crashes and is started again under both sites: each loses its session, joins the room
# again (made anew), publishes and subscribes again, and the two connect with a new handshake.
kill -KILL "$janus"
wait "$janus" 2>/dev/null || true
janus_killed_ns=$(date +%s%N)
sleep 1
"$RT_TEST_START_JANUS" "$PWD/janus" "$RT_TEST_NAMESPACE_ADDRESS" &
janus=$!
wait_for_events site_A connection_restored 2 || fail "site A did not connect again after Janus restarted"
wait_for_events site_B_again connection_restored 1 || fail "site B did not connect again after Janus restarted"
echo "Janus killed, started again 1 s later: both sites connected again $(( ($(date +%s%N) - janus_killed_ns) / 1000000 )) ms after it went"
sleep 3  # the call going on a while, for the figures since
for site in "$b" "$a"; do
  kill -INT "$site"
  set +e
  wait "$site"
  status=$?
  set -e
  [ "$status" -eq 130 ] || fail "a site stopped with SIGINT ended with $status"
done
/usr/bin/python3 - <<'PY' || fail "the sites' metrics"
import json
def events(folder):
    return [json.loads(line) for line in open(f"{folder}/events.jsonl")]
# B's first run was killed: its events say what it felt.
b1 = events("site_B")
assert sum(e["event"] == "touch_start" for e in b1) == 1 and sum(e["event"] == "motor_pulse" for e in b1) >= 1, "site B's first clap"
for folder in ["site_A", "site_B_again"]:
    m = json.load(open(f"{folder}/metrics.json"))
    t = m["transport"]
    assert t["kind"] == "webrtc-janus", (folder, t["kind"])
    assert m["connected"] is True, folder
    assert t["portraits"]["received"] > 0, (folder, t["portraits"])
    assert t["messages"]["refused"] == 0, (folder, t["messages"], t["last_error"])
    print(f"{folder}: through Janus room 7: {t['portraits']['received']} portraits received, "
          f"{t['messages']['received']} messages, {t['messages']['refused']} refused, "
          f"{m['touch']['starts']} touch(es)")
m = json.load(open("site_B_again/metrics.json"))
assert m["transport"]["data_channels_sealed"] is True, m["transport"]
assert m["touch"]["starts"] == 1, m["touch"]
assert sum(e["event"] == "motor_pulse" for e in events("site_B_again")) >= 1
# A: the other site left (killed), came back, and left again (stopped before A); the second clap
# came after the rejoin. Then both lost Janus once and joined again, and the records since opened
# under the new handshake's keys.
a = json.load(open("site_A/metrics.json"))
t = a["transport"]
assert t["other_site_left"] == 2 and t["other_site_rejoins"] == 1, {k: t[k] for k in ("other_site_left", "other_site_rejoins")}
for folder in ["site_A", "site_B_again"]:
    tj = json.load(open(f"{folder}/metrics.json"))["transport"]
    assert tj["janus_lost"] == 1 and tj["janus_rejoins"] == 1 and tj["last_janus_outage_s"] > 0, (folder, tj)
    print(f"{folder}: Janus lost and joined again: connected again {tj['last_janus_outage_s']:.2f} s after the loss; since: "
          f"{tj['since_rejoin']['portraits_received']} portraits, {tj['since_rejoin']['messages_received']} messages, "
          f"{tj['since_rejoin']['messages_refused']} refused")
assert a["touch"]["starts"] == 2, a["touch"]
ev = events("site_A")
restored = [e["t_us"] for e in ev if e["event"] == "connection_restored"]
lost = [e for e in ev if e["event"] == "connection_lost"]
assert len(restored) == 2 and len(lost) >= 2, "site A's connection_lost / connection_restored"
assert "waiting for it to come back" in lost[0]["reason"], lost[0]
assert "connection to Janus was lost" in lost[1]["reason"], lost[1]
after = lambda kind: sum(e["event"] == kind and restored[0] < e["t_us"] < restored[1] for e in ev)
assert after("touch_start") == 1 and after("motor_pulse") >= 1, (after("touch_start"), after("motor_pulse"))
since = t["since_rejoin"]
assert since["portraits_received"] > 0 and since["messages_received"] > 0 and since["messages_refused"] == 0, since
assert json.load(open("site_B_again/metrics.json"))["transport"]["since_rejoin"]["messages_received"] > 0
b2 = events("site_B_again")
b2_wait = [e["t_us"] for e in b2 if e["event"] == "waiting_for_peer"][0]
b2_connected = [e["t_us"] for e in b2 if e["event"] == "connected"][0]
print(f"site A: the other site away {t['last_rejoin_s']['away']:.1f} s (its restart included), connected again "
      f"{t['last_rejoin_s']['back_to_connected']:.2f} s after it published again; "
      f"touches after the rejoin {after('touch_start')}, motor pulses {after('motor_pulse')}; "
      f"touches dropped while away {t['touches_dropped_while_away']}")
print(f"site B started again: connected {(b2_connected - b2_wait) / 1e6:.2f} s after it began waiting for site A")
PY
trap 'kill $janus 2>/dev/null; wait $janus 2>/dev/null || true' EXIT
# A wrong pin: refused by Janus, and said so.
set +e
timeout 60 "$binary" site --site A --scene clap --frames 95 "${small[@]}" --room 7 --room-secret wrong_pin.txt --out site_A_wrong --connect-timeout 10 > w.out 2> w.err
status=$?
set -e
[ "$status" -ne 0 ] || fail "a site with the wrong pin ran"
grep -qi "pin" w.err || fail "the wrong pin was not named: $(tail -3 w.err)"
echo "wrong pin: refused ($(grep -i -m1 pin w.err))"
# A Janus whose rooms only its administrator makes, and no room 8 in it.
kill "$janus"; wait "$janus" 2>/dev/null || true
"$RT_TEST_START_JANUS" "$PWD/janus_admin" "$RT_TEST_NAMESPACE_ADDRESS" an-admin-key &
janus=$!
for _ in $(seq 100); do
  (exec 3<>/dev/tcp/127.0.0.1/8188) 2>/dev/null && break
  sleep 0.1
done
set +e
timeout 60 "$binary" site --site A --scene clap --frames 95 "${small[@]}" --room 8 --out site_A_no_room --connect-timeout 10 > n.out 2> n.err
status=$?
set -e
[ "$status" -ne 0 ] || fail "a site ran in a room that does not exist"
grep -q "making room 8 was refused" n.err || fail "the refused room was not explained: $(tail -3 n.err)"
echo "no such room: refused ($(grep -m1 "making room 8" n.err))"
