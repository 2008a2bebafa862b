#!/usr/bin/env bash
# Two sites meet in a Janus room and clap, neither listening for the other: a Janus started in
# the network namespace the test runs in (tests/cli/in_network_namespace.sh), both sites with
# --transport webrtc --janus --room --room-secret. Each must connect through the room, see the
# other's portraits, seal its data channels with the site key, and feel the clap once. A site
# given a wrong pin is refused with Janus's reason, and so is one that asks a Janus which makes
# rooms for its administrator only for a room that does not exist. Exits 77 (skipped) where there
# is no namespace or no Janus.
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
small=(--scene clap --frames 95 --width 64 --height 36 --resolution-scale 0.05 --motor simulated --display headless
       --transport webrtc --janus ws://127.0.0.1:8188 --key-file session.key)
"$binary" site --site A "${small[@]}" --room 7 --room-secret pin.txt --out site_A > a.out 2> a.err &
a=$!
"$binary" site --site B "${small[@]}" --room 7 --room-secret pin.txt --out site_B > b.out 2> b.err || fail "site B failed"
wait "$a" || fail "site A failed"
/usr/bin/python3 - <<'PY' || fail "the sites' metrics"
import json
for site in "AB":
    m = json.load(open(f"site_{site}/metrics.json"))
    t = m["transport"]
    assert t["kind"] == "webrtc-janus", (site, t["kind"])
    assert m["connected"] is True, site
    assert t["data_channels_sealed"] is True, (site, t)
    assert t["portraits"]["received"] > 0, (site, t["portraits"])
    assert t["messages"]["refused"] == 0, (site, t["messages"], t["last_error"])
    assert m["touch"]["starts"] == 1, (site, m["touch"])
    print(f"site {site}: through Janus room 7: {t['portraits']['received']} portraits received, "
          f"{t['messages']['received']} messages, sealed, one touch")
PY
# A wrong pin: refused by Janus, and said so.
set +e
timeout 60 "$binary" site --site A "${small[@]}" --room 7 --room-secret wrong_pin.txt --out site_A_wrong --connect-timeout 10 > w.out 2> w.err
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
timeout 60 "$binary" site --site A "${small[@]}" --room 8 --out site_A_no_room --connect-timeout 10 > n.out 2> n.err
status=$?
set -e
[ "$status" -ne 0 ] || fail "a site ran in a room that does not exist"
grep -q "making room 8 was refused" n.err || fail "the refused room was not explained: $(tail -3 n.err)"
echo "no such room: refused ($(grep -m1 "making room 8" n.err))"
