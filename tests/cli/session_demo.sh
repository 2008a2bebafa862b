#!/usr/bin/env bash
# `remotetouch demo` end to end, tiny: two site processes over loopback on a few frames of a scene.
#   session_demo.sh BINARY OUT SCENE FRAMES TOUCHES [extra demo arguments...]
# TOUCHES: the touch starts (and motor pulses) each site must report: 1 for clap, 0 for miss/wave.
# With --disconnect-after-ms among the extra arguments, the log must also show the link lost
# during the run and restored, and the run must still finish with the same touches.
# GESTURE (environment, default palm): the gesture every touch_start, motor_pulse and
# remote_touch_start must name. Only palm touches are predicted; others pulse when seen.
set -euo pipefail
binary=$1 out=$2 scene=$3 frames=$4 touches=$5
shift 5
rm -rf "$out"
mkdir -p "$(dirname "$out")"  # for the log beside it, before the demo makes $out
"$binary" demo --scene "$scene" --frames "$frames" --width 96 --height 54 --resolution-scale 0.1 --time-scale 1 \
  --out "$out" "$@" 2>&1 | tee "$out.log"
fail() { echo "FAIL: $*" >&2; exit 1; }
for site in A B; do
  for f in metrics.json events.jsonl frames.jsonl site.mp4 frames/frame_0000.png; do
    [ -s "$out/site_$site/$f" ] || fail "missing $out/site_$site/$f"
  done
  ls "$out/site_$site/truth/"frame_*.png > /dev/null || fail "no ground truth frames at site $site"
  starts=$(grep -c "\"event\":\"touch_start\".*\"site\":\"$site\"" "$out/events.jsonl" || true)
  pulses=$(grep -c "\"event\":\"motor_pulse\".*\"site\":\"$site\"" "$out/events.jsonl" || true)
  if [ "$starts" -ne "$touches" ]; then
    grep -E '"event":"(touch_|remote_touch_|connection_)' "$out/events.jsonl" >&2 || true
    fail "site $site: $starts touch starts, expected $touches"
  fi
  [ "$pulses" -eq "$touches" ] || fail "site $site: $pulses motor pulses, expected $touches"
done
# Each site's composite must look like the other site's user: a misplaced portrait or hand
# drops the PSNR against the ground truth far below this (about 20 dB at this tiny size).
/usr/bin/python3 - "$out/metrics.json" <<'PY' || fail "PSNR against the ground truth too low or missing"
import json, sys
m = json.load(open(sys.argv[1]))
for site in "AB":
    final, mean = m["psnr_db"][site]["final_db"], m["psnr_db"][site]["mean_db"]
    print(f"site {site}: PSNR final {final} dB, mean {mean} dB over {m['psnr_db'][site]['frames']} frames")
    assert final is not None and final > 15 and mean > 15
    # A portrait's waits before its turn are part of its capture-to-screen latency, frame by frame.
    stages, latency = m["sites"][site]["stage_wall_ms"], m["sites"][site]["latency_ms"]
    on_screen = latency["capture_to_portrait_on_screen"]
    for wait in ("portrait_queue_wait", "display_turn_wait"):
        assert stages[wait]["count"] >= on_screen["count"] > 0, (site, wait, stages[wait], on_screen)
        assert 0 <= stages[wait]["median_ms"] <= on_screen["median_ms"], (site, wait, stages[wait], on_screen)
PY
# Contact prediction (on by default) times each clap's pulse against the scene's true contact, and
# nothing is predicted, cancelled or felt where the palms never meet. Where the link is cut, the
# remote palm's arrival at the glass can only reach this site once the link is back: each pulse may
# come late by the time this site's link was down after the contact, and by no more than the
# slack below on top of it (the proxy's delay and jitter, a tracker period, the touch loop's tick).
GESTURE=${GESTURE:-palm} /usr/bin/python3 - "$out" "$touches" "$@" <<'PY' || fail "contact prediction not used or mistimed"
import json, os, sys
out, touches, extra = sys.argv[1], int(sys.argv[2]), sys.argv[3:]
gesture = os.environ["GESTURE"]
m = json.load(open(f"{out}/metrics.json"))
events = [json.loads(line) for line in open(f"{out}/events.jsonl")]
link_cut = any(a.startswith("--disconnect") or a.startswith("--loss") for a in extra)
SLACK_AFTER_DOWNTIME_MS, PREDICTION_LEAD_MS = 250, 500

def downtime_us(site, begin, end):
    """Time in [begin, end] this site's link spent between a connection_lost and the next restore."""
    total, lost_at = 0, None
    for e in events:
        if e.get("site") != site:
            continue
        if e["event"] == "connection_lost" and lost_at is None:
            lost_at = e["t_us"]
        elif e["event"] == "connection_restored" and lost_at is not None:
            total += max(0, min(e["t_us"], end) - max(lost_at, begin))
            lost_at = None
    if lost_at is not None:
        total += max(0, end - max(lost_at, begin))
    return total

for site in "AB":
    touch = m["sites"][site]["touch"]
    pulses, timing = touch["pulses"], touch["contact_to_vibration_ms"]
    print(f"site {site}: pulses {pulses}, contact to vibration median {timing['median_ms']} ms")
    assert touch["settings"]["contact_prediction"] == "on", touch["settings"]
    assert timing["contacts"] == touches, timing
    if touches == 0:
        assert timing["vibrations_without_contact"] == 0, timing
        assert pulses == {"predicted": 0, "confirmed": 0, "cancelled": 0, "unpredicted": 0}, pulses
    elif not link_cut and gesture != "palm":
        assert timing["vibrations_without_contact"] == 0, timing
        assert pulses["predicted"] == 0 and pulses["unpredicted"] == touches, pulses
        assert timing["contacts_not_felt"] == 0, timing
    elif not link_cut:
        assert timing["vibrations_without_contact"] == 0, timing
        # A clean run times its clap's vibration on the contact, and cancels nothing. The predictor
        # usually times it; where it had no fit yet when the skin touched (one run in a few on a
        # loaded machine), the pulse leaves at detection, which the timing below still holds.
        assert pulses["predicted"] + pulses["unpredicted"] == touches and pulses["cancelled"] == 0, pulses
        assert timing["contacts_not_felt"] == 0, timing
        assert abs(timing["median_ms"]) <= 60, timing
    else:
        commands = [e["t_us"] for e in events if e["event"] == "motor_pulse" and e.get("site") == site]
        contacts = [t["contact_us"] for t in timing["touches"]]
        assert len(commands) == len(contacts), (commands, contacts)
        for contact, command in zip(contacts, commands):
            down = downtime_us(site, contact, command) if command > contact else 0
            late_ms = (command - contact - down) / 1000
            print(f"site {site}: motor command {(command - contact) / 1000:.1f} ms after the contact, "
                  f"{down / 1000:.1f} ms of it with the link down")
            assert (command - contact) / 1000 >= -PREDICTION_LEAD_MS, (contact, command)
            assert late_ms <= SLACK_AFTER_DOWNTIME_MS, (contact, command, down)
PY
# The touch's sound, where the sites have loudspeakers: one per pulse, heard in each audio.wav at the
# moment the vibration is felt.
if [[ " $* " != *" --sound none"* ]]; then
  /usr/bin/python3 "$(dirname "$0")/check_touch_sound.py" "$out" "$touches" || fail "touch sound missing or mistimed"
  # Lips and words together: the far voice's latency within ITU-R BT.1359's window around the far
  # portrait's (45 ms early to 125 ms late). Portraits later than the hold can wait for (a machine
  # too loaded to show them in time) are reported, not judged.
  /usr/bin/python3 - "$out/metrics.json" <<'PY' || fail "the far voice is not held to the far portrait"
import json, sys
m = json.load(open(sys.argv[1]))
HOLD_REACH_MS = 350
for site in "AB":
    offset = m["sites"][site]["sound"].get("voice_minus_portrait_ms")
    portrait = m["sites"][site]["latency_ms"]["capture_to_portrait_on_screen"]["median_ms"]
    print(f"site {site}: voice latency - portrait latency {offset} ms (portraits {portrait} ms after capture)")
    assert offset is not None, "no voice or no portrait latency"
    if portrait > HOLD_REACH_MS:
        print(f"site {site}: not judged: the portraits came later than the voice is held for")
        continue
    assert -45 <= offset <= 125, offset
PY
fi
# Every touch names its gesture, at the site that saw it, at its motor, and at the other site.
GESTURE=${GESTURE:-palm} /usr/bin/python3 - "$out" "$touches" <<'PY' || fail "a touch event names the wrong gesture"
import json, os, sys
out, touches, gesture = sys.argv[1], int(sys.argv[2]), os.environ["GESTURE"]
events = [json.loads(line) for line in open(f"{out}/events.jsonl")]
for site in "AB":
    for name in ("touch_start", "motor_pulse", "remote_touch_start"):
        named = [e.get("gesture") for e in events if e["event"] == name and e.get("site") == site]
        print(f"site {site}: {name} gestures {named}")
        assert all(g == gesture for g in named), (site, name, named, gesture)
        if name != "remote_touch_start":
            assert len(named) == touches, (site, name, named)
PY
# Each displayed frame says what appearance the drawn hand was shaded with, and only where one was drawn.
/usr/bin/python3 - "$out" "$touches" <<'PY' || fail "frames.jsonl: drawn_hand_appearance missing or wrong"
import json, sys
out, touches = sys.argv[1], int(sys.argv[2])
for site in "AB":
    drawn = 0
    for line in open(f"{out}/site_{site}/frames.jsonl"):
        row = json.loads(line)
        if "hand_pose" not in row:
            continue  # e.g. a link-lost frame
        appearance = row["drawn_hand_appearance"]
        assert isinstance(row["appearance_fitted_from_this_frame"], bool), row
        if row["hand_pose"] in ("interpolated", "held"):
            drawn += 1
            assert appearance["state"] in ("waiting", "fitted", "stale"), row
            assert appearance["frames_fitted"] >= 0 and isinstance(appearance["provisional"], bool), row
        else:
            assert appearance is None, row
    print(f"site {site}: {drawn} frames with the mesh hand drawn")
    assert touches == 0 or drawn > 0, "a touching scene drew no mesh hand"
PY
grep -q '"capture_to_portrait_on_screen"' "$out/metrics.json" || fail "no portrait latency in metrics.json"
grep -q "touch_to_motor_command median ms" "$out.log" || fail "no summary table"
if [[ " $* " =~ " --"(loss|delay-ms|jitter-ms|disconnect-after-ms)" " ]]; then
  grep -q '"fault_proxy"' "$out/metrics.json" || fail "fault options given, but no fault proxy counts in metrics.json"
fi
if [[ " $* " == *" --loss "* ]]; then
  grep -q '"records_dropped": [1-9]' "$out/metrics.json" || fail "--loss given, but the proxy dropped no record"
fi
if [[ " $* " == *" --disconnect-after-ms "* ]]; then
  grep -q '"event":"connection_lost".*"phase":"run"' "$out/events.jsonl" || fail "no connection_lost during the run"
  grep -q '"event":"connection_restored".*"phase":"run"' "$out/events.jsonl" || fail "no connection_restored during the run"
  grep -q '"fault_proxy"' "$out/metrics.json" || fail "no fault proxy counts in metrics.json"
fi
if [[ " $* " == *" --outage-ms "* ]]; then
  # The link stayed down long enough for the displays to notice: they kept running and said so.
  for site in A B; do
    grep -q '"link_lost":true' "$out/site_$site/frames.jsonl" || fail "site $site showed no link-lost frame during the outage"
  done
fi
echo "session demo ($scene) ok"
