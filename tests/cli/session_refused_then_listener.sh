#!/usr/bin/env bash
# A site whose peer address first answers with something else: an older release's listener, which
# replies with its version 2 hello. Site B is refused, says why, and keeps trying (a refusal is
# not the end); the real site A comes up on that port within B's connect timeout and gets the
# call: both run to the end.
set -euo pipefail
binary=$1 out=$2
rm -rf "$out"
mkdir -p "$out"
head -c 32 /dev/urandom | od -An -v -tx1 | tr -d ' \n' > "$out/session.key"
chmod 600 "$out/session.key"
# The fake listener: one connection, answered with a version 2 hello (magic, version 2, the
# listener's role, a reserved 0, nonce and ephemeral key), then it goes and frees the port.
python3 - "$out" <<'PY' &
import os, socket, sys, time
out = sys.argv[1]
server = socket.socket()
server.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
server.bind(("127.0.0.1", 0))
server.listen(8)
with open(out + "/fake.port.tmp", "w") as f:
    f.write(str(server.getsockname()[1]))
os.rename(out + "/fake.port.tmp", out + "/fake.port")
server.settimeout(120)
connection, _ = server.accept()
connection.settimeout(10)
connection.recv(112)
connection.sendall(b"RTHS" + bytes([2, 0, 2, 0]) + bytes(64))
time.sleep(0.5)
connection.close()
server.close()
PY
fake=$!
for _ in $(seq 1 600); do [ -f "$out/fake.port" ] && break; sleep 0.1; done
port=$(cat "$out/fake.port")
common=(--scene clap --frames 10 --width 32 --height 18 --resolution-scale 0.05 --connect-timeout 60 --key-file "$out/session.key")
"$binary" site --site B --peer "127.0.0.1:$port" --out "$out/B" "${common[@]}" > "$out/b.out" 2> "$out/b.err" &
b=$!
refusal='^site B: the other site refused the connection \(handshake: the peer speaks protocol version 2, this build version 3'
for _ in $(seq 1 1200); do grep -qE "$refusal" "$out/b.err" && break; kill -0 "$b" 2> /dev/null || break; sleep 0.1; done
wait "$fake"
grep -qE "$refusal" "$out/b.err" || { echo "site B never told the fake's refusal" >&2; cat "$out/b.err" >&2; kill "$b" 2> /dev/null; exit 1; }
kill -0 "$b" 2> /dev/null || { echo "site B ended at the refusal" >&2; cat "$out/b.err" >&2; exit 1; }
# The real listener, on the port the fake had.
"$binary" site --site A --listen "127.0.0.1:$port" --out "$out/A" "${common[@]}" > "$out/a.out" 2> "$out/a.err" &
a=$!
set +e
wait "$b"
b_status=$?
wait "$a"
a_status=$?
set -e
cat "$out/a.err" "$out/b.err"
[ "$b_status" -eq 0 ] || { echo "site B exit status $b_status, expected 0" >&2; exit 1; }
[ "$a_status" -eq 0 ] || { echo "site A exit status $a_status, expected 0" >&2; exit 1; }
grep -q "^connected" "$out/b.out" || { echo "site B never connected" >&2; exit 1; }
grep -q "^done" "$out/b.out" || { echo "site B did not finish" >&2; exit 1; }
echo "site B was refused by a fake listener, kept trying, and got the real one when it came up"
