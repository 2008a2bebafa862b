#!/usr/bin/env bash
# Two sites holding different keys: the handshake is refused by both, and each site gives up
# after its connect timeout with exit status 2 and the reason, instead of running unprotected.
set -euo pipefail
binary=$1 out=$2
rm -rf "$out"
mkdir -p "$out"
printf '%064d\n' 1 > "$out/a.key"
printf '%064d\n' 2 > "$out/b.key"
common=(--scene clap --frames 10 --width 32 --height 18 --resolution-scale 0.05 --connect-timeout 4)
# Site A from a config file (its key file named relative to the config), B from flags.
cat > "$out/a.json" <<JSON
{"scene": "clap", "site": "A", "listen": "127.0.0.1:0", "key_file": "a.key", "frames": 10, "width": 32, "height": 18,
 "resolution_scale": 0.05}
JSON
"$binary" site --config "$out/a.json" --connect-timeout 4 --out "$out/A" > "$out/a.out" 2> "$out/a.err" &
a=$!
for _ in $(seq 1 600); do grep -q "listening on" "$out/a.out" && break; sleep 0.1; done
port=$(sed -n 's/^listening on //p' "$out/a.out")
[ -n "$port" ] || { echo "site A never listened" >&2; cat "$out/a.err" >&2; exit 1; }
set +e
"$binary" site --site B --peer "127.0.0.1:$port" --key-file "$out/b.key" --out "$out/B" "${common[@]}" > "$out/b.out" 2> "$out/b.err"
b_status=$?
wait "$a"
a_status=$?
set -e
cat "$out/a.err" "$out/b.err"
[ "$a_status" -eq 2 ] || { echo "site A exit status $a_status, expected 2" >&2; exit 1; }
[ "$b_status" -eq 2 ] || { echo "site B exit status $b_status, expected 2" >&2; exit 1; }
grep -qi "no connection to the other site" "$out/b.err"
grep -qi "refused\|proof\|key" "$out/b.err"
if grep -q "^connected" "$out/a.out" "$out/b.out"; then echo "a site connected with the wrong key" >&2; exit 1; fi
echo "wrong key refused by both sites"
