#!/usr/bin/env python3
"""Sound against picture in a two-site demo of the av-marker scene, as a viewer sees and hears it.

    check_av_marker.py OUT

Each user claps and their shirt flashes white at the same instants (the scene's av_marker). At
each site, the other user's flashes are found in what the site showed (the mean brightness of
its frames, each at its display time in frames.jsonl) and the claps in what it played
(audio.wav, each sample at its play time); both are found again in site.mp4, its picture and
its sound on the file's own clock. Each marker's sound minus
picture is printed. Every marker must be seen and heard. The offset is judged against ITU-R
BT.1359's window (sound at most 45 ms early, 125 ms late) where the site showed the other user
smoothly enough for the window to mean anything: at least MIN_DISPLAY_FPS frames a second and
portraits at most MAX_PORTRAIT_LATENCY_MS after their capture; otherwise it is reported only.
"""
import array
import json
import os
import subprocess
import sys
import tempfile
import wave

RATE = 48000
WINDOW = RATE // 1000                 # 1 ms of energy
EARLIEST_MS, LATEST_MS = -45.0, 125.0  # sound minus picture, ITU-R BT.1359
MIN_DISPLAY_FPS, MAX_PORTRAIT_LATENCY_MS = 20.0, 350.0
# A flash turns the other user's shirt white: the frame's mean brightness jumps by far more than
# any motion of an idle user moves it.
FLASH_JUMP = 3.0                      # of 255, mean over the frame
SMALL = (32, 18)                      # the video, scaled down to this to be read
PAUSE_MS = 300                        # between two claps or two flashes, at least
PAIR_MS = 500                         # a clap this far from its flash is another marker's
SCENE_FPS = 30                        # the av-marker scene's: site.mp4 runs at it times the time scale


def ms_energies(samples, channels):
    frames = len(samples) // channels
    out = []
    for ms in range(frames // WINDOW):
        begin, end = ms * WINDOW * channels, (ms + 1) * WINDOW * channels
        out.append(sum((s / 32768.0) ** 2 for s in samples[begin:end]) / (WINDOW * channels))
    return out


def clap_onsets(energies):
    """The milliseconds where the energy first passes a tenth of the loudest millisecond after at
    least PAUSE_MS below it: the claps (the users say nothing else)."""
    peak = max(energies) if energies else 0.0
    if peak <= 0.0:
        return []
    onsets, last = [], -10 ** 9
    for ms, e in enumerate(energies):
        if e >= peak / 10.0:
            if ms - last > PAUSE_MS:
                onsets.append(ms)
            last = ms
    return onsets


def flash_onsets(brightness, times_ms):
    """The times of the frames where the brightness jumps up by FLASH_JUMP over the frame before:
    the first frame of each flash shown."""
    onsets = []
    for i in range(1, len(brightness)):
        if brightness[i] - brightness[i - 1] >= FLASH_JUMP and (not onsets or times_ms[i] - onsets[-1] > PAUSE_MS):
            onsets.append(times_ms[i])
    return onsets


def read_wav(path):
    with wave.open(path) as wav:
        return wav.getnchannels(), array.array("h", wav.readframes(wav.getnframes()))


def decode(video, folder):
    """site.mp4's picture as SMALL grey frames (mean brightness each) and its sound as a WAV."""
    raw, sound = os.path.join(folder, "picture.raw"), os.path.join(folder, "sound.wav")
    picture = subprocess.run(["gst-launch-1.0", "-q", "filesrc", f"location={video}", "!", "qtdemux", "name=d", "d.video_0", "!",
                              "queue", "!", "decodebin", "!", "videoconvert", "!", "videoscale", "!",
                              f"video/x-raw,format=GRAY8,width={SMALL[0]},height={SMALL[1]}", "!", "filesink", f"location={raw}"],
                             capture_output=True, text=True, timeout=120)
    audio = subprocess.run(["gst-launch-1.0", "-q", "filesrc", f"location={video}", "!", "qtdemux", "name=d", "d.audio_0", "!",
                            "queue", "!", "avdec_aac", "!", "audioconvert", "!", "audio/x-raw,format=S16LE,channels=2", "!",
                            "wavenc", "!", "filesink", f"location={sound}"], capture_output=True, text=True, timeout=120)
    if picture.returncode != 0 or audio.returncode != 0:
        return None
    data = open(raw, "rb").read()
    size = SMALL[0] * SMALL[1]
    brightness = [sum(data[i:i + size]) / size for i in range(0, len(data) - size + 1, size)]
    return brightness, read_wav(sound)


def pair(flashes_ms, claps_ms):
    """Each flash with the clap nearest it, within half the markers' spacing: sound minus picture
    in ms; a flash without one is not counted."""
    offsets = []
    for f in flashes_ms:
        nearest = min((c - f for c in claps_ms), key=abs, default=None)
        if nearest is not None and abs(nearest) <= PAIR_MS:
            offsets.append(nearest)
    return offsets


def judge(site, what, offsets, markers, smooth, failures):
    shown = ", ".join(f"{o:+.0f}" for o in offsets)
    print(f"site {site}: {what}: sound minus picture {shown} ms over {len(offsets)} of {markers} markers")
    if len(offsets) != markers:
        failures.append(f"site {site}: {what}: {len(offsets)} markers seen and heard, not {markers}")
    elif smooth and not all(EARLIEST_MS <= o <= LATEST_MS for o in offsets):
        failures.append(f"site {site}: {what}: sound minus picture {shown} ms, outside {EARLIEST_MS:+.0f}..{LATEST_MS:+.0f}")


def main():
    out = sys.argv[1]
    metrics = json.load(open(f"{out}/metrics.json"))
    failures = []
    for site in "AB":
        other = "B" if site == "A" else "A"
        m = metrics["sites"][site]
        if m["scene"] != "av-marker":
            failures.append(f"site {site} played the scene {m['scene']}, not av-marker")
            continue
        markers = len(metrics["sites"][other]["sound"].get("marker_claps_us", []))
        if markers == 0:
            failures.append(f"site {other} clapped no marker: is the scene av-marker?")
            continue
        fps = m["fps"]["display"]
        latency = m["latency_ms"]["capture_to_portrait_on_screen"]["median_ms"] or 0.0
        smooth = fps >= MIN_DISPLAY_FPS and latency <= MAX_PORTRAIT_LATENCY_MS
        if not smooth:
            print(f"site {site}: shown at {fps:.1f} fps, portraits {latency:.0f} ms after capture: the window is not judged here")
        # What the site showed and played, each on this site's clock.
        frames = [json.loads(line) for line in open(f"{out}/site_{site}/frames.jsonl")]
        shown_ms = [f["t_us"] / 1000.0 for f in frames]
        with tempfile.TemporaryDirectory() as folder:
            from_png = subprocess.run(["gst-launch-1.0", "-q", "multifilesrc", f"location={out}/site_{site}/frames/frame_%04d.png",
                                       "index=0", f"stop-index={len(frames) - 1}", "caps=image/png,framerate=30/1", "!", "pngdec", "!",
                                       "videoconvert", "!", "videoscale", "!",
                                       f"video/x-raw,format=GRAY8,width={SMALL[0]},height={SMALL[1]}", "!", "filesink",
                                       f"location={folder}/frames.raw"], capture_output=True, text=True, timeout=120)
            data = open(f"{folder}/frames.raw", "rb").read() if from_png.returncode == 0 else b""
        size = SMALL[0] * SMALL[1]
        brightness = [sum(data[i:i + size]) / size for i in range(0, len(data) - size + 1, size)]
        channels, samples = read_wav(f"{out}/site_{site}/audio.wav")
        start_ms = m["sound"]["audio_wav"]["start_us"] / 1000.0
        claps = [start_ms + ms for ms in clap_onsets(ms_energies(samples, channels))]
        judge(site, "on screen and from the loudspeakers", pair(flash_onsets(brightness, shown_ms), claps), markers, smooth,
              failures)
        with tempfile.TemporaryDirectory() as folder:
            decoded = decode(f"{out}/site_{site}/site.mp4", folder)
        if not decoded:
            failures.append(f"site {site}: site.mp4's picture or sound could not be decoded")
            continue
        brightness, (v_channels, v_samples) = decoded
        video_ms = [i * 1000.0 / (SCENE_FPS * m["time_scale"]) for i in range(len(brightness))]
        claps = clap_onsets(ms_energies(v_samples, v_channels))
        judge(site, "in site.mp4", pair(flash_onsets(brightness, video_ms), claps), markers, smooth, failures)
    for failure in failures:
        print("FAIL:", failure, file=sys.stderr)
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
