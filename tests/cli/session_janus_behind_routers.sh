#!/usr/bin/env bash
# Two offices behind routers that translate addresses and let nothing in (tests/cli/behind_routers.sh)
# meet through a Janus on the public side and clap: neither site can reach the other, only Janus.
# Site A reaches Janus over ws://, site B over wss:// with the certificate Janus was started with as
# its authority. Each must connect through the room, see the other's portraits, seal its data
# channels with the site key and feel the clap once; each router must have carried the call's UDP.
# Exits 77 (skipped) where the namespaces or Janus cannot be had.
#   session_janus_behind_routers.sh BINARY OUT
set -euo pipefail
binary=$1 out=$2
if [ -z "${RT_TEST_PUBLIC_ADDRESS:-}" ]; then echo "SKIPPED: not behind the test's routers (run through behind_routers.sh)"; exit 77; fi
if [ ! -x /usr/bin/janus ]; then echo "SKIPPED: /usr/bin/janus is missing: apt-get install janus"; exit 77; fi
here=$(cd "$(dirname "$0")" && pwd)
rm -rf "$out"
mkdir -p "$out"
cd "$out"
fail() {
  echo "FAIL: $*" >&2
  for f in *.err; do echo "== $f" >&2; tail -30 "$f" >&2; done
  exit 1
}
public=$RT_TEST_PUBLIC_ADDRESS
RT_JANUS_LISTEN=$public "$here/start_janus.sh" "$PWD/janus" "$public" &
janus=$!
trap 'kill $janus 2>/dev/null; wait $janus 2>/dev/null || true' EXIT
for _ in $(seq 100); do
  (exec 3<>"/dev/tcp/$public/8188") 2>/dev/null && break
  sleep 0.1
done
"$binary" keygen session.key > /dev/null
echo "a pin of the room" > pin.txt
small=(--scene clap --frames 95 --width 64 --height 36 --resolution-scale 0.05 --motor simulated --display headless
       --transport webrtc --key-file session.key --room 9 --room-secret pin.txt)
ip netns exec office_a "$binary" site --site A "${small[@]}" --janus "ws://$public:8188" --out site_A > a.out 2> a.err &
a=$!
ip netns exec office_b "$binary" site --site B "${small[@]}" --janus "wss://$public:8989" --janus-ca janus/janus-cert.pem \
  --out site_B > b.out 2> b.err || fail "site B failed"
wait "$a" || fail "site A failed"
for site in a b; do
  ip netns exec "router_$site" nft list chain ip filter forward > "router_$site.txt"
done
/usr/bin/python3 - <<'PY' || fail "the sites' metrics"
import json, re
for site in "AB":
    m = json.load(open(f"site_{site}/metrics.json"))
    t = m["transport"]
    assert t["kind"] == "webrtc-janus", (site, t["kind"])
    assert m["connected"] is True, site
    assert t["data_channels_sealed"] is True, (site, t)
    assert t["portraits"]["received"] > 0, (site, t["portraits"])
    assert t["messages"]["refused"] == 0, (site, t["messages"], t["last_error"])
    assert m["touch"]["starts"] == 1, (site, m["touch"])
    # The UDP each router carried out of its office (the call's ICE and media), and back in.
    rules = open(f"router_{site.lower()}.txt").read()
    out = int(re.search(r'meta l4proto udp counter packets (\d+)', rules).group(1))
    back = int(re.search(r'established,related meta l4proto udp counter packets (\d+)', rules).group(1))
    assert out > 100 and back > 100, (site, out, back)
    latency = m["latency_ms"]["capture_to_portrait_on_screen"]
    print(f"site {site} behind its router ({'ws' if site == 'A' else 'wss'} to Janus): {t['portraits']['received']} portraits, "
          f"{t['messages']['received']} messages received, sealed, one touch; the router forwarded {out} UDP packets out "
          f"and {back} back in; portrait capture to screen median {latency['median_ms']:.0f} ms (p90 {latency['p90_ms']:.0f})")
PY
