#!/usr/bin/env bash
# A site whose cameras run live, as a user runs one: the fake libk4a.so.1.4 serves k4a recordings
# as connected devices, each giving a capture a frame period after its previous one.
#   1. `simulate --format k4a` writes wave's site A; a scene names a site file whose cameras are
#      those devices ("source": "k4a", by serial); `demo` runs it: site A takes its frame sets from
#      the devices, sends portraits, and site B shows them.
#      What `record` writes from them replays as a site, without a tracker recording.
#   2. Two devices whose colour lens is 3 cm from the depth lens (test_k4a_live's), run by hand as
#      `site --site-file` against a simulated `site`: their depth is registered into colour.
#   3. Bad live sites: no library, an unknown serial, fewer cameras than --views, --site-file with
#      --replay: clear errors.
#   k4a_site_live.sh BINARY OUT FAKE_LIBRARY WAVE_SCENE DEFAULT_SITE LENSES_APART_DIR
set -euo pipefail
source "$(dirname "$0")/listening.sh"
binary=$1 out=$2 fake=$3 wave=$4 default_site=$5 apart=$6
rm -rf "$out"
mkdir -p "$out"
fail() { echo "FAIL: $*" >&2; exit 1; }

"$binary" simulate --scene wave --format k4a --resolution-scale 1 --frames 10 --gt-width 64 --gt-height 36 \
  --out "$out/recordings" > "$out/simulate.out"
recordings=$(/usr/bin/python3 -c '
import json, sys
site = json.load(open(sys.argv[1] + "/site.json"))
print(":".join(sys.argv[1] + "/" + c["name"] + ".mkv" for c in site["cameras"]))' "$out/recordings")
export REMOTETOUCH_K4A_LIBRARY=$fake REMOTETOUCH_FAKE_K4A_PACED=1 REMOTETOUCH_FAKE_K4A_RECORDINGS=$recordings
"$binary" list-cameras > "$out/list.out"
# The live site: the recordings' site file, each camera the device of its recording by serial.
/usr/bin/python3 - "$out" "$wave" "$default_site" <<'PY'
import json, sys
out, wave, default_site = sys.argv[1:]
serials = [line.split()[1] for line in open(f"{out}/list.out") if line.startswith("  serial ")]
site = json.load(open(f"{out}/recordings/site.json"))
assert len(serials) == len(site["cameras"]), (serials, len(site["cameras"]))
depth_modes = {(320, 288): "NFOV_2X2BINNED", (640, 576): "NFOV_UNBINNED", (512, 512): "WFOV_2X2BINNED",
               (1024, 1024): "WFOV_UNBINNED"}
for camera, serial in zip(site["cameras"], serials):
    assert serial.endswith(camera["name"]), (serial, camera["name"])
    depth = camera["depth"]
    camera["source"] = "k4a"
    camera["k4a"] = {"serial": serial, "color_mode": "MJPG_720P",
                     "depth_mode": depth_modes[(depth["width"], depth["height"])], "fps": 30}
json.dump(site, open(f"{out}/live_site.json", "w"), indent=2)
scene = json.load(open(wave))
scene["sites"]["A"]["site"] = f"{out}/live_site.json"
scene["sites"]["B"]["site"] = default_site
json.dump(scene, open(f"{out}/live_scene.json", "w"), indent=2)
PY

# 1. The demo, site A live.
"$binary" demo --scene "$out/live_scene.json" --frames 30 --width 64 --height 36 --display headless \
  --out "$out/demo" > "$out/demo.out" 2> "$out/demo.err" || { cat "$out/demo.err"; fail "the demo failed"; }
grep -q "6 live k4a cameras from '$out/live_site.json'" "$out/demo.err" || { cat "$out/demo.err"; fail "site A did not say it runs live"; }
/usr/bin/python3 - "$out" <<'PY' || fail "demo metrics"
import json, math, sys
out = sys.argv[1]
a = json.load(open(f"{out}/demo/site_A/metrics.json"))
b = json.load(open(f"{out}/demo/site_B/metrics.json"))
print(f"site A: {a['inputs']}, captured {a['frames']['captured']}, portraits sent {a['frames']['portraits_sent']}, "
      f"live {a['live_cameras']}; site B displayed {b['frames']['displayed']}")
assert a["inputs"] == f"live k4a cameras of {out}/live_site.json", a["inputs"]
assert a["live_cameras"] == {"cameras": 6, "skipped_captures": 0}, a["live_cameras"]
# The devices give 10 captures each; a set is one capture of each, never more sets than captures.
assert 1 <= a["frames"]["captured"] <= 10, a["frames"]
assert a["frames"]["portraits_sent"] >= 1, a["frames"]
assert a["depth_registered_cameras"] == 0  # the simulator's lenses are aligned
assert a["fps"]["capture"] > 0 and math.isfinite(a["fps"]["capture"])
assert b["frames"]["displayed"] >= 1, b["frames"]
PY

# 1b. What `record` writes from those devices replays as site A (`demo --replay-a` runs `site
#     --replay`): cameras without a tracker recording, which the site says, sending no hands.
"$binary" record --site "$out/live_site.json" --seconds 20 --out "$out/recorded" > "$out/record.out" 2>&1 ||
  { cat "$out/record.out"; fail "record failed"; }
[ ! -e "$out/recorded/tracker.jsonl" ] || fail "record wrote a tracker.jsonl: the replay below tests the folder without one"
"$binary" demo --scene wave --replay-a "$out/recorded" --frames 10 --width 64 --height 36 --display headless \
  --out "$out/demo-recorded" > "$out/demo-recorded.out" 2> "$out/demo-recorded.err" ||
  { cat "$out/demo-recorded.err"; fail "the demo replaying what record wrote failed"; }
grep -q "has no tracker.jsonl .*no tracked hands are sent" "$out/demo-recorded.err" ||
  { cat "$out/demo-recorded.err"; fail "the replay did not say that it has no tracked hands"; }
/usr/bin/python3 - "$out" <<'PY' || fail "metrics of the replay of what record wrote"
import json, sys
out = sys.argv[1]
a = json.load(open(f"{out}/demo-recorded/site_A/metrics.json"))
b = json.load(open(f"{out}/demo-recorded/site_B/metrics.json"))
print(f"site A: {a['inputs']}, tracker {a['tracker']['source']}, captured {a['frames']['captured']}, "
      f"portraits sent {a['frames']['portraits_sent']}; site B displayed {b['frames']['displayed']}")
assert a["inputs"] == f"replay of {out}/recorded", a["inputs"]
assert a["tracker"]["source"] == "none: the recording has no tracker.jsonl", a["tracker"]
assert a["frames"]["portraits_sent"] >= 1 and b["frames"]["displayed"] >= 1
PY

# 2. Lenses apart, by hand: `site --site-file` (live) against a simulated site.
head -c 32 /dev/urandom | od -An -v -tx1 | tr -d ' \n' > "$out/session.key"
chmod 600 "$out/session.key"
common=(--width 64 --height 36 --frames 5 --views 2 --display headless --motor simulated --key-file "$out/session.key")
export REMOTETOUCH_FAKE_K4A_RECORDINGS=$apart/top-left.mkv:$apart/top-centre.mkv
"$binary" site --site A --site-file "$apart/live.json" "${common[@]}" --listen 127.0.0.1:0 --out "$out/site_A" \
  > "$out/site_A.out" 2> "$out/site_A.err" &
a_pid=$!
port=$(listening_port "$out/site_A.out" "$a_pid")
[ -n "$port" ] || { cat "$out/site_A.err"; fail "site A never listened"; }
"$binary" site --site B "${common[@]}" --peer "127.0.0.1:$port" --resolution-scale 0.1 --out "$out/site_B" \
  > "$out/site_B.out" 2> "$out/site_B.err" || { cat "$out/site_B.err"; fail "site B failed"; }
wait "$a_pid" || { cat "$out/site_A.err"; fail "site A (live) failed"; }
grep -q "2 of 2 cameras have their depth registered into their colour image" "$out/site_A.err" ||
  { cat "$out/site_A.err"; fail "the live cameras' depth was not registered"; }
/usr/bin/python3 - "$out" <<'PY' || fail "site metrics"
import json, sys
out = sys.argv[1]
a = json.load(open(f"{out}/site_A/metrics.json"))
b = json.load(open(f"{out}/site_B/metrics.json"))
print(f"site A (lenses apart): {a['inputs']}, registered {a['depth_registered_cameras']}, "
      f"portraits sent {a['frames']['portraits_sent']}; site B displayed {b['frames']['displayed']}")
assert a["depth_registered_cameras"] == 2
assert a["frames"]["depth_registered"] == a["frames"]["captured"] >= 1, a["frames"]
assert a["frames"]["portraits_sent"] >= 1 and b["frames"]["displayed"] >= 1
PY

# 3. Bad live sites.
expect_error() {  # NAME REGEX ARGS...: exit status not 0, the message on stderr
  local name=$1 regex=$2
  shift 2
  set +e
  "$@" > "$out/$name.out" 2> "$out/$name.err"
  local status=$?
  set -e
  [ "$status" -ne 0 ] || fail "$name: exit status 0"
  grep -Eq -- "$regex" "$out/$name.err" || { cat "$out/$name.err"; fail "$name: no message matching '$regex'"; }
}
alone=(site --site A --frames 2 --width 64 --height 36 --display headless --motor simulated --connect-timeout 5
       --key-file "$out/session.key")
expect_error no-library "need the k4a library, and '/nonexistent/libk4a.so.1.4' could not be loaded" \
  env REMOTETOUCH_K4A_LIBRARY=/nonexistent/libk4a.so.1.4 "$binary" "${alone[@]}" --views 2 --site-file "$apart/live.json" \
  --out "$out/no-library"
sed 's/fake-001/fake-999/' "$apart/live.json" > "$out/unknown_serial.json"
expect_error unknown-serial "k4a device 'fake-999' is not connected: the connected devices are 'fake-001'" \
  "$binary" "${alone[@]}" --views 2 --site-file "$out/unknown_serial.json" \
  --out "$out/unknown-serial"
expect_error too-few-cameras "live.json' has 2 cameras; the image-based model uses 4 \(--views\)" \
  "$binary" "${alone[@]}" --site-file "$apart/live.json" --out "$out/too-few-cameras"
expect_error with-replay "--site-file and --replay both" \
  "$binary" "${alone[@]}" --site-file "$apart/live.json" --replay "$out/recordings" --out "$out/with-replay"
echo "live k4a cameras as a site's cameras: ok"
