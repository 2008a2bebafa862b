#!/usr/bin/env bash
# Two sites holding different keys: the handshake is refused, instead of running unprotected. The
# listener A refuses B's hello (its MAC is of another key) before it makes any handshake state,
# and closes; the connector B takes that for what it is, says so at each attempt, keeps trying
# with back-off (a refusal may be temporary: a stranger's or an older listener on the address, a
# key being replaced) and gives up at its connect timeout with the reason. A waits out its own
# for the right peer. Both end with exit status 2 and the reason.
set -euo pipefail
source "$(dirname "$0")/listening.sh"
binary=$1 out=$2
rm -rf "$out"
mkdir -p "$out"
head -c 32 /dev/urandom | od -An -v -tx1 | tr -d ' \n' > "$out/a.key"
head -c 32 /dev/urandom | od -An -v -tx1 | tr -d ' \n' > "$out/b.key"
chmod 600 "$out/a.key" "$out/b.key"
b_timeout=6
common=(--scene clap --frames 10 --width 32 --height 18 --resolution-scale 0.05 --connect-timeout "$b_timeout")
# Site A from a config file (its key file named relative to the config), B from flags. A waits
# longer than B tries, so that every attempt of B's meets A.
cat > "$out/a.json" <<JSON
{"scene": "clap", "site": "A", "listen": "127.0.0.1:0", "key_file": "a.key", "frames": 10, "width": 32, "height": 18,
 "resolution_scale": 0.05}
JSON
"$binary" site --config "$out/a.json" --connect-timeout 12 --out "$out/A" > "$out/a.out" 2> "$out/a.err" &
a=$!
port=$(listening_port "$out/a.out" "$a")
[ -n "$port" ] || { echo "site A never listened" >&2; cat "$out/a.err" >&2; exit 1; }
set +e
SECONDS=0
"$binary" site --site B --peer "127.0.0.1:$port" --key-file "$out/b.key" --out "$out/B" "${common[@]}" > "$out/b.out" 2> "$out/b.err"
b_status=$?
b_seconds=$SECONDS
wait "$a"
a_status=$?
set -e
cat "$out/a.err" "$out/b.err"
[ "$a_status" -eq 2 ] || { echo "site A exit status $a_status, expected 2" >&2; exit 1; }
[ "$b_status" -eq 2 ] || { echo "site B exit status $b_status, expected 2" >&2; exit 1; }
# What each side says of a peer without the key (net/session.cpp), what the connecting site says
# at each refusal and when it gives up (site/site_run.cpp).
at_listener='handshake: the hello is not authenticated with our session key (a stranger, or the wrong key on one side)'
at_connector='the listener closed the connection without a hello: it did not take ours (the wrong session key on one side?), or it is turning connections away'
expect_line() {  # FILE EXTENDED-REGEX WHO
  grep -qE "$2" "$1" || { echo "$3: no line matching '$2' in $1" >&2; exit 1; }
}
escape() { printf '%s' "$1" | sed 's/[]().?*+[]/\\&/g'; }
expect_line "$out/a.err" "^\[site A\] connection with 127\.0\.0\.1:[0-9]+ refused: $(escape "$at_listener")" "site A (listener)"
expect_line "$out/b.err" "^\[site B\] connection with 127\.0\.0\.1:$port refused: $(escape "$at_connector")" "site B (connector)"
# Refused, told, tried again: more than once, each time with the reason.
retries=$(grep -cE "^site B: the other site refused the connection \($(escape "$at_connector")\)( \(and [0-9]+ more attempts\))?; trying again for up to [0-9.]+ s\$" "$out/b.err" || true)
[ "$retries" -ge 2 ] || { echo "site B told $retries refusals with their reason and tried again, expected 2 or more" >&2; exit 1; }
expect_line "$out/b.err" "^site B: no connection to the other site within $b_timeout s of the start \(refused: $(escape "$at_connector")\)\$" "site B"
# Not before its connect timeout (a refusal is not the end), nor long after it.
[ "$b_seconds" -ge $((b_timeout - 1)) ] || { echo "site B gave up after ${b_seconds} s, before its ${b_timeout} s connect timeout" >&2; exit 1; }
[ "$b_seconds" -lt $((b_timeout + 10)) ] || { echo "site B took ${b_seconds} s to give up" >&2; exit 1; }
if grep -q "not trying again" "$out/b.err"; then echo "site B gave up at a refusal" >&2; exit 1; fi
expect_line "$out/a.err" "^site A: no connection to the other site within 12 s of the start \(" "site A"
if grep -q "^connected" "$out/a.out" "$out/b.out"; then echo "a site connected with the wrong key" >&2; exit 1; fi
echo "wrong key refused by both sites; site B told each refusal and tried again until its connect timeout ($retries refusals told, ${b_seconds} s)"
