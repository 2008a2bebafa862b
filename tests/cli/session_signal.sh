#!/usr/bin/env bash
# A site stopped by a signal stops cleanly: SIGTERM mid-run ends its stages and writes its
# metrics.json (stopped_by: SIGTERM) and an event, exit status 143, and its peer sees the
# connection end and finishes; SIGINT while it waits for its peer ends the wait at once (130).
#   session_signal.sh BINARY OUT
set -euo pipefail
source "$(dirname "$0")/listening.sh"
binary=$1 out=$2
rm -rf "$out"
mkdir -p "$out"
fail() { echo "FAIL: $*" >&2; exit 1; }
# A random key: a hand-made one (a padded number) is refused as too regular to be a secret.
head -c 32 /dev/urandom | od -An -v -tx1 | tr -d ' \n' > "$out/session.key"
chmod 600 "$out/session.key"
common=(--scene clap --frames 115 --width 96 --height 54 --resolution-scale 0.1 --time-scale 1 --connect-timeout 60
        --key-file "$out/session.key")

"$binary" site --site A --listen 127.0.0.1:0 "${common[@]}" --out "$out/A" > "$out/a.out" 2> "$out/a.err" &
a=$!
port=$(listening_port "$out/a.out" "$a")
[ -n "$port" ] || { kill "$a"; fail "site A never listened"; }
"$binary" site --site B --peer "127.0.0.1:$port" "${common[@]}" --out "$out/B" > "$out/b.out" 2> "$out/b.err" &
b=$!
for _ in $(seq 1 600); do grep -q "^connected" "$out/a.out" && break; sleep 0.1; done
grep -q "^connected" "$out/a.out" || { kill "$a" "$b"; fail "the sites never connected"; }
# Mid-run: once site A has captured a frame (its ground truth follows each) and displayed one of
# B's, waited for rather than assumed after a fixed time, which a loaded machine can outlast.
mid_run() { compgen -G "$out/A/truth/frame_*.png" > /dev/null && compgen -G "$out/A/frames/frame_*.png" > /dev/null; }
for _ in $(seq 1 600); do mid_run && break; kill -0 "$a" 2> /dev/null || break; sleep 0.1; done
mid_run || { kill "$a" "$b" 2> /dev/null || true; fail "site A captured or displayed no frame"; }
kill -TERM "$a" || { kill "$b" 2> /dev/null || true; fail "site A ended by itself before the SIGTERM: its scene was over"; }
set +e
wait "$a"; a_status=$?
wait "$b"; b_status=$?
set -e
cat "$out/a.err" "$out/b.err"
[ "$a_status" -eq 143 ] || fail "site A exited with $a_status after SIGTERM, expected 143"
[ "$b_status" -lt 128 ] || fail "site B crashed (exit status $b_status)"
grep -q "site A: SIGTERM: stopping" "$out/a.err" || fail "site A did not say why it stopped"
grep -q '"event":"stopped"' "$out/A/events.jsonl" || fail "no stopped event"
/usr/bin/python3 - "$out/A/metrics.json" <<'PY' || fail "site A's metrics"
import json, sys
m = json.load(open(sys.argv[1]))
assert m["stopped_by"] == "SIGTERM", m.get("stopped_by")
assert m["frames"]["captured"] > 0 and "gpu_ms" in m
print("site A stopped by", m["stopped_by"], "after", m["frames"]["captured"], "captured frames")
PY

# SIGINT while waiting for a peer that never comes: at once, not after --connect-timeout (60 s).
"$binary" site --site A --listen 127.0.0.1:0 "${common[@]}" --out "$out/alone" > "$out/alone.out" 2> "$out/alone.err" &
alone=$!
[ -n "$(listening_port "$out/alone.out" "$alone")" ] || fail "the lone site never listened"
start=$(date +%s%N)
kill -INT "$alone"
set +e
wait "$alone"; alone_status=$?
set -e
elapsed_ms=$(( ($(date +%s%N) - start) / 1000000 ))
[ "$alone_status" -eq 130 ] || fail "a waiting site exited with $alone_status after SIGINT, expected 130"
# Well before the connect timeout, with room for a loaded machine.
[ "$elapsed_ms" -lt 20000 ] || fail "a waiting site took $elapsed_ms ms to stop"
grep -q "SIGINT before the other site connected" "$out/alone.err" || fail "the waiting site did not say why it stopped"
/usr/bin/python3 - "$out/alone/metrics.json" <<'PY' || fail "the waiting site's metrics"
import json, sys
m = json.load(open(sys.argv[1]))
assert m["stopped_by"] == "SIGINT" and m["connected"] is False and m["phase"] == "waiting_for_peer", m
PY

# SIGTERM while the site is still starting (its device up, its cameras not yet searched for the
# user's eyes): it stops there and still writes metrics.json.
"$binary" site --site A --listen 127.0.0.1:0 "${common[@]}" --out "$out/starting" > "$out/starting.out" 2> "$out/starting.err" &
starting=$!
# The device line comes once the stop handlers are in place, before the eye search and the listen.
for _ in $(seq 1 600); do grep -q "remotetouch: using '" "$out/starting.err" && break; sleep 0.05; done
grep -q "remotetouch: using '" "$out/starting.err" || fail "the starting site never said which device it uses"
kill -TERM "$starting"
set +e
wait "$starting"; starting_status=$?
set -e
[ "$starting_status" -eq 143 ] || fail "a starting site exited with $starting_status after SIGTERM, expected 143"
/usr/bin/python3 - "$out/starting/metrics.json" <<'PY' || fail "the starting site's metrics"
import json, sys
m = json.load(open(sys.argv[1]))
assert m["stopped_by"] == "SIGTERM" and m["connected"] is False, m
PY
echo "stopped cleanly by signals"
