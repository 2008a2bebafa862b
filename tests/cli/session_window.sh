#!/usr/bin/env bash
# A site with a window (`site --display both`) on a virtual X server (Xvfb; lavapipe presents to
# X11): it plays a short clap against a headless site B. P holds the picture, S writes a
# screenshot, and the window as the X server shows it (xwd) matches the composite the site wrote
# for the frame on screen; F1 shows the fused depth instead; a resized window gets a new
# swapchain and the picture keeps its aspect; Esc ends the site cleanly, its metrics written, and
# the validation layer saw no error.
#   session_window.sh BINARY OUT
set -euo pipefail
source "$(dirname "$0")/listening.sh"
binary=$1 out=$2
rm -rf "$out"
mkdir -p "$out"
fail() { echo "FAIL: $*" >&2; exit 1; }
# wait_for SECONDS COMMAND...: runs COMMAND every 0.1 s until it succeeds (status 0), or fails
# (status 1) once SECONDS have passed. What it waits for takes a second or two; the deadlines are
# for a loaded machine, where a fixed sleep would be too short.
wait_for() {
  local deadline=$((SECONDS + $1))
  shift
  until "$@"; do
    [ "$SECONDS" -lt "$deadline" ] || return 1
    sleep 0.1
  done
}
for tool in Xvfb xdotool xwd; do command -v "$tool" > /dev/null || fail "$tool is missing (scripts/packages.txt)"; done
# A random key: a hand-made one (a padded number) is refused as too regular to be a secret.
head -c 32 /dev/urandom | od -An -v -tx1 | tr -d ' \n' > "$out/session.key"
chmod 600 "$out/session.key"
common=(--scene clap --width 96 --height 54 --resolution-scale 0.1 --connect-timeout 60 --key-file "$out/session.key")

# -displayfd: the server picks a free display number and writes it once it accepts clients.
Xvfb -displayfd 3 -screen 0 320x240x24 -nolisten tcp 3> "$out/display" 2> "$out/xvfb.err" &
xvfb=$!
pids=($xvfb)
trap 'kill "${pids[@]}" 2> /dev/null || true' EXIT
wait_for 20 test -s "$out/display" || fail "Xvfb did not start: $(cat "$out/xvfb.err")"
export DISPLAY=":$(head -n1 "$out/display")"

# A slow scene clock: the keys below land while site A is still playing.
"$binary" site --site A --listen 127.0.0.1:0 --display both --validation --time-scale 0.25 "${common[@]}" --out "$out/A" \
  > "$out/a.out" 2> "$out/a.err" &
a=$!
pids+=($a)
port=$(listening_port "$out/a.out" "$a")
[ -n "$port" ] || { cat "$out/a.err" >&2; fail "site A never listened"; }
env -u DISPLAY "$binary" site --site B --peer "127.0.0.1:$port" --time-scale 0.25 "${common[@]}" --out "$out/B" \
  > "$out/b.out" 2> "$out/b.err" &
b=$!
pids+=($b)
# Three frames on screen: each displayed frame's PNG is written once the window has shown it
# (frames.jsonl is buffered, and would tell only later).
wait_for 120 test -e "$out/A/frames/frame_0002.png" || { cat "$out/a.err" >&2; fail "site A displayed no frames"; }

window=
find_window() { window=$(xdotool search --name "RemoteTouch site A" 2> /dev/null | head -n1) && [ -n "$window" ]; }
wait_for 20 find_window || fail "no window named 'RemoteTouch site A' on $DISPLAY"
timeout 20 xdotool windowfocus --sync "$window" 2> /dev/null || xdotool windowfocus "$window"
press() { xdotool key --clearmodifiers "$1"; }
screenshots() { grep -c '"event":"screenshot"' "$out/A/events.jsonl" || true; }
has_screenshots() { [ "$(screenshots)" -ge "$1" ]; }
wait_screenshots() { wait_for 30 has_screenshots "$1" || fail "site A wrote no screenshot $1 after S"; }
# window_shows XWD PNG: the window as the X server shows it (dumped into XWD) is PNG's picture, at
# most one step apart on all but a few pixels. window_shows XWD bars W H: it is W x H, a picture
# between four rows of black above and below (96x54 kept at its aspect in 200x120). The window
# shows what the site presented only once the presentation engine has put it on screen.
window_shows() {
  xwd -silent -id "$window" -out "$1" 2> /dev/null || return 1
  /usr/bin/python3 - "$@" <<'PY'
import struct, sys
import numpy as np
from PIL import Image

data = open(sys.argv[1], "rb").read()
header = struct.unpack(">25I", data[:100])  # X11/XWDFile.h; the format check_window.py reads
width, height, byte_order, bytes_per_line, colors = header[4], header[5], header[7], header[12], header[19]
start = header[0] + colors * 12
rows = np.frombuffer(data[start:start + height * bytes_per_line], dtype=np.uint8).reshape(height, bytes_per_line)
pixels = rows[:, :width * 4].copy().view("<u4" if byte_order == 0 else ">u4").reshape(height, width)
screen = np.dstack([((pixels & m) >> ((m & -m).bit_length() - 1)).astype(int) for m in header[14:17]])
if sys.argv[2] == "bars":
    shows = screen.shape[:2] == (int(sys.argv[4]), int(sys.argv[3])) and (screen[:4] == 0).all() \
        and (screen[-4:] == 0).all() and screen[4:-4].mean() > 20
else:
    shot = np.asarray(Image.open(sys.argv[2]).convert("RGB")).astype(int)
    shows = screen.shape == shot.shape and (np.abs(screen - shot) <= 1).all(axis=2).mean() >= 0.999
sys.exit(0 if shows else 1)
PY
}

press p
wait_for 20 grep -q '"paused":true' "$out/A/events.jsonl" || fail "P did not pause the window"
press s
wait_screenshots 1
# The window as check_window.py compares it with the composite: once it shows the held picture.
wait_for 20 window_shows "$out/window.xwd" "$out/A/screenshots/window_0000.png" ||
  fail "the window never showed the picture P held (the first screenshot); see $out/window.xwd"
press F1
press s
wait_screenshots 2
# Back to the composite, going on, in a window of another shape: a new swapchain, bars added.
press F8
press p
timeout 20 xdotool windowsize --sync "$window" 200 120 2> /dev/null || xdotool windowsize "$window" 200 120
wait_for 20 window_shows "$out/window-resized.xwd" bars 200 120 ||
  fail "the resized window never showed the picture between bars; see $out/window-resized.xwd"
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
