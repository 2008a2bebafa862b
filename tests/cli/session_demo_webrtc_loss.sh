#!/usr/bin/env bash
# `remotetouch demo --transport webrtc --packet-loss 0.02`: each site's video loses 2 % of its RTP
# packets at random (GStreamer's netsim). The clap must still give one touch start and one pulse
# per site (session_demo.sh's checks), each touch event must reach the other site once (none lost,
# none repeated: the touch events travel on the reliable data channel, which the simulated loss
# does not touch, so this holds the call's bookkeeping to it), and each site's metrics must show the
# loss and its repair: packets lost on the wire, a track that broke recovering (within 2 s here).
#   session_demo_webrtc_loss.sh BINARY OUT SCENE FRAMES TOUCHES
set -euo pipefail
binary=$1 out=$2 scene=$3 frames=$4 touches=$5
here=$(cd "$(dirname "$0")" && pwd)
"$here/session_demo.sh" "$binary" "$out" "$scene" "$frames" "$touches" --transport webrtc --packet-loss 0.02
/usr/bin/python3 - "$out" "$touches" <<'PY'
import json, sys
out, touches = sys.argv[1], int(sys.argv[2])
m = json.load(open(f"{out}/metrics.json"))
assert m["transport"] == "webrtc" and m["packet_loss"] == 0.02, (m["transport"], m.get("packet_loss"))
events = [json.loads(line) for line in open(f"{out}/events.jsonl")]
def count(kind, site):
    return sum(1 for e in events if e.get("event") == kind and e.get("site") == site)
for site, other in (("A", "B"), ("B", "A")):
    call = m["sites"][site]["transport"]
    net, tracks = call["network"], call["tracks"]
    print(f"site {site}: network {net}")
    for name, t in tracks.items():
        print(f"site {site}: {name} {t}")
    assert net["simulated_loss"] == 0.02, net
    assert call["portraits"]["received"] > 0 and call["messages"]["refused"] == 0, call
    # What this site received of the other's touch events: each once.
    for kind in ("touch_start", "touch_end"):
        sent, received = count(kind, other), count("remote_" + kind, site)
        assert sent == touches and received == sent, (site, kind, sent, received)
    # The voice as an audio track: it came, each packet a voice frame, and the longest dropout is
    # printed (test_media_webrtc_voice holds it to 60 ms; here two sites render beside it).
    voice = tracks["voice"]
    assert voice["packets_received"] > 0 and voice["packets_refused"] == 0, voice
    print(f"site {site}: voice jitter buffer {m['sites'][site]['sound']['voice']['jitter']}")
    for name in ("color", "depth_alpha"):
        t = tracks[name]
        assert t["recovered"] + 1 >= t["losses"], (site, name, t)  # at most the last still open at the end
        # The goal is a correct picture within 500 ms of a break; with RTCP told the call's
        # bandwidth a keyframe request goes within tens of ms, and the breaks seen took 70-240 ms
        # (docs/webrtc.md). Held to 1 s, twice the goal, for the sites' loaded cores; while RTCP
        # went a second apart at this size breaks took 1.1 and 1.4 s, which this fails.
        assert t["recovery_ms_max"] <= 1000, (site, name, t)
# The loss happened: between the two sites' four incoming tracks some packets went missing (what
# retransmission repaired is not counted there, so the sender's view from the receiver reports
# counts too).
lost = sum(m["sites"][s]["transport"]["tracks"][n]["packets_lost_past_repair"] for s in "AB" for n in ("color", "depth_alpha"))
reported = max(m["sites"][s]["transport"]["network"]["reported_loss"] for s in "AB")
print(f"packets lost past repair, both sites: {lost}; largest loss a receiver reported: {reported:.3f}")
assert lost > 0 or reported > 0, (lost, reported)
PY
echo "webrtc demo ($scene) under 2 % packet loss: same touches, each touch event once"
