#!/usr/bin/env bash
# A site with a window (`site --display both`) on a virtual X server (Xvfb; lavapipe presents to
# X11): it plays a short clap against a headless site B. P holds the picture, S writes a
# screenshot, and the window as the X server shows it (xwd) matches the composite the site wrote
# for the frame on screen; F1 shows the fused depth instead; a resized window gets a new
# swapchain and the picture keeps its aspect; Esc ends the site cleanly, its metrics written, and
# the validation layer saw no error.
#   session_window.sh BINARY OUT
set -euo pipefail
binary=$1 out=$2
rm -rf "$out"
mkdir -p "$out"
fail() { echo "FAIL: $*" >&2; exit 1; }
for tool in Xvfb xdotool xwd; do command -v "$tool" > /dev/null || fail "$tool is missing (scripts/packages.txt)"; done
printf '%064d\n' 42 > "$out/session.key"
chmod 600 "$out/session.key"
common=(--scene clap --width 96 --height 54 --resolution-scale 0.1 --connect-timeout 60 --key-file "$out/session.key")

# -displayfd: the server picks a free display number and writes it once it accepts clients.
Xvfb -displayfd 3 -screen 0 320x240x24 -nolisten tcp 3> "$out/display" 2> "$out/xvfb.err" &
xvfb=$!
pids=($xvfb)
trap 'kill "${pids[@]}" 2> /dev/null || true' EXIT
for _ in $(seq 1 100); do [ -s "$out/display" ] && break; sleep 0.1; done
[ -s "$out/display" ] || fail "Xvfb did not start: $(cat "$out/xvfb.err")"
export DISPLAY=":$(head -n1 "$out/display")"

# A slow scene clock: the keys below land while site A is still playing.
"$binary" site --site A --listen 127.0.0.1:0 --display both --validation --time-scale 0.25 "${common[@]}" --out "$out/A" \
  > "$out/a.out" 2> "$out/a.err" &
a=$!
pids+=($a)
for _ in $(seq 1 600); do grep -q "listening on" "$out/a.out" && break; sleep 0.1; done
port=$(sed -n 's/^listening on //p' "$out/a.out")
[ -n "$port" ] || { cat "$out/a.err" >&2; fail "site A never listened"; }
env -u DISPLAY "$binary" site --site B --peer "127.0.0.1:$port" --time-scale 0.25 "${common[@]}" --out "$out/B" \
  > "$out/b.out" 2> "$out/b.err" &
b=$!
pids+=($b)
for _ in $(seq 1 1200); do [ "$(wc -l < "$out/A/frames.jsonl" 2> /dev/null || echo 0)" -ge 3 ] && break; sleep 0.1; done
[ "$(wc -l < "$out/A/frames.jsonl")" -ge 3 ] || { cat "$out/a.err" >&2; fail "site A displayed no frames"; }

window=$(xdotool search --name "RemoteTouch site A" | head -n1)
[ -n "$window" ] || fail "no window named 'RemoteTouch site A' on $DISPLAY"
xdotool windowfocus --sync "$window" 2> /dev/null || xdotool windowfocus "$window"
press() { xdotool key --clearmodifiers "$1"; }
screenshots() { grep -c '"event":"screenshot"' "$out/A/events.jsonl" || true; }
wait_screenshots() {
  for _ in $(seq 1 300); do [ "$(screenshots)" -ge "$1" ] && return 0; sleep 0.1; done
  fail "site A wrote no screenshot $1 after S"
}

press p
for _ in $(seq 1 100); do grep -q '"paused":true' "$out/A/events.jsonl" && break; sleep 0.1; done
grep -q '"paused":true' "$out/A/events.jsonl" || fail "P did not pause the window"
sleep 0.5
press s
wait_screenshots 1
xwd -silent -id "$window" -out "$out/window.xwd"
press F1
press s
wait_screenshots 2
# Back to the composite, going on, in a window of another shape: a new swapchain, bars added.
press F8
press p
xdotool windowsize --sync "$window" 200 120 2> /dev/null || xdotool windowsize "$window" 200 120
sleep 1.5
press s
wait_screenshots 3
press Escape
set +e
wait "$a"; a_status=$?
wait "$b"; b_status=$?
set -e
cat "$out/a.err" "$out/b.err"
[ "$a_status" -eq 0 ] || fail "site A exited with $a_status after Esc, expected 0"
[ "$b_status" -lt 128 ] || fail "site B crashed (exit status $b_status)"
/usr/bin/python3 "$(dirname "$0")/check_window.py" "$out" || fail "the window's pictures or metrics"
