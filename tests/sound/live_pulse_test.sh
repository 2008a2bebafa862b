#!/bin/bash
# The live audio path against a real sound server: a PulseAudio server of the test's own (a null
# sink, a private socket, no cookie), the hidden [.pulse] test case against it, and the server
# stopped by its process id however the test ends.
# Usage: live_pulse_test.sh CPU_TEST_EXECUTABLE OUTPUT_DIR
set -euo pipefail
tests="$1"
dir="$(realpath -m "$2")"
if ! command -v pulseaudio > /dev/null; then
  echo "the live audio test needs a PulseAudio server: apt-get install pulseaudio (scripts/packages.txt)" >&2
  exit 1
fi
rm -rf "$dir"
mkdir -p "$dir"
socket="$dir/native"
HOME="$dir" XDG_RUNTIME_DIR="$dir" pulseaudio -n --daemonize=no --exit-idle-time=-1 --use-pid-file=no \
  --load="module-null-sink sink_name=rt_null rate=48000" \
  --load="module-native-protocol-unix socket=$socket auth-anonymous=1" > "$dir/pulseaudio.log" 2>&1 &
server=$!
trap 'kill "$server" 2> /dev/null || true; wait "$server" 2> /dev/null || true' EXIT
for _ in $(seq 100); do
  [ -S "$socket" ] && break
  kill -0 "$server" 2> /dev/null || { cat "$dir/pulseaudio.log" >&2; exit 1; }
  sleep 0.05
done
[ -S "$socket" ] || { echo "PulseAudio did not open $socket" >&2; cat "$dir/pulseaudio.log" >&2; exit 1; }
PULSE_SERVER="unix:$socket" "$tests" --filenames-as-tags "[.pulse]"
