#!/usr/bin/env bash
# Two sites holding different keys: the handshake is refused by both, instead of running
# unprotected. The connector B gives up at its first refusal (the same key cannot succeed), well
# before its connect timeout; the listener A waits out its own for the right peer. Both end with
# exit status 2 and the reason.
set -euo pipefail
binary=$1 out=$2
rm -rf "$out"
mkdir -p "$out"
printf '%064d\n' 1 > "$out/a.key"
printf '%064d\n' 2 > "$out/b.key"
chmod 600 "$out/a.key" "$out/b.key"
common=(--scene clap --frames 10 --width 32 --height 18 --resolution-scale 0.05 --connect-timeout 30)
# Site A from a config file (its key file named relative to the config), B from flags.
cat > "$out/a.json" <<JSON
{"scene": "clap", "site": "A", "listen": "127.0.0.1:0", "key_file": "a.key", "frames": 10, "width": 32, "height": 18,
 "resolution_scale": 0.05}
JSON
"$binary" site --config "$out/a.json" --connect-timeout 6 --out "$out/A" > "$out/a.out" 2> "$out/a.err" &
a=$!
for _ in $(seq 1 600); do grep -q "listening on" "$out/a.out" && break; sleep 0.1; done
port=$(sed -n 's/^listening on //p' "$out/a.out")
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
# What each side of the handshake says of a peer without the key (net/secure_channel.cpp,
# net/session.cpp), and what each site says when it gives up (app/site_runner.cpp).
wrong_key='handshake refused: the peer did not prove knowledge of the session key (wrong key?)'
expect_line() {  # FILE EXTENDED-REGEX WHO
  grep -qE "$2" "$1" || { echo "$3: no line matching '$2' in $1" >&2; exit 1; }
}
escaped=$(printf '%s' "$wrong_key" | sed 's/[]().?*+[]/\\&/g')
expect_line "$out/a.err" "^\[site A\] connection with 127\.0\.0\.1:[0-9]+ refused: $escaped\$" "site A (listener)"
expect_line "$out/b.err" "^\[site B\] connection with 127\.0\.0\.1:$port refused: $escaped\$" "site B (connector)"
expect_line "$out/b.err" "^site B: the other site refused the connection \($escaped\); not trying again\$" "site B"
[ "$b_seconds" -lt 15 ] || { echo "site B took ${b_seconds} s to give up on a refused key" >&2; exit 1; }
# A's last reason is its last refusal, unless B quit in the middle of a handshake (A then saw it
# close): only the giving up is checked here.
expect_line "$out/a.err" "^site A: no connection to the other site within 6 s of the start \(" "site A"
if grep -q "^connected" "$out/a.out" "$out/b.out"; then echo "a site connected with the wrong key" >&2; exit 1; fi
echo "wrong key refused by both sites"
