#!/usr/bin/env python3
"""Sound against picture in a two-site demo of the av-marker scene, as a viewer sees and hears it.

    check_av_marker.py OUT

Each user claps and their shirt flashes white at the same instants (the scene's av_marker): the
clap is in the microphone at the capture time of the first camera frame of the flash. At each
site, the other user's flashes are found in what the site showed (the mean brightness of its
frames, each at its display time in frames.jsonl) and the claps in what it played (audio.wav,
each sample at its play time); both are found again in site.mp4, its picture and its sound on the
file's own clock. Every marker must be seen and heard. Each marker's sound minus picture is
printed, and on screen taken apart: the voice's latency (capture to loudspeaker) less the frames
the picture skipped (the first flash frame shown was captured this long after the flash began)
and less that frame's latency (capture to screen).

The offset is judged against ITU-R BT.1359's window (sound at most 45 ms early, 125 ms late) at
each marker the site showed smoothly enough for the window to mean anything: over the STEADY_MS
to the flash's first frame shown, at least MIN_DISPLAY_FPS pictures a second, none taken or shown
more than two display periods after the one before (a slower screen shows a flash up to a
whole display period late, and a stalled one as late as the stall, whatever the sound does), and
that frame at most MAX_PORTRAIT_LATENCY_MS after its capture (the most the voice is held);
elsewhere it is reported only. The same markers are judged in site.mp4.
"""
import array
import json
import math
import os
import subprocess
import sys
import tempfile
import wave

RATE = 48000
WINDOW = RATE // 1000                 # 1 ms of energy
EARLIEST_MS, LATEST_MS = -45.0, 125.0  # sound minus picture, ITU-R BT.1359
MIN_DISPLAY_FPS, MAX_PORTRAIT_LATENCY_MS = 20.0, 350.0
STEADY_MS = 500.0                     # the display's rate is judged over this long before a flash
# A flash turns the other user's shirt white: the frame's mean brightness jumps by far more than
# any motion of an idle user moves it.
FLASH_JUMP = 3.0                      # of 255, mean over the frame
SMALL = (32, 18)                      # the video, scaled down to this to be read
PAUSE_MS = 300                        # between two claps or two flashes, at least
PAIR_MS = 500                         # a clap this far from its flash is another marker's
SCENE_FPS = 30                        # the av-marker scene's: site.mp4 runs at it times the time scale
SCENE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "assets", "scenes", "av-marker.json")


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


def flash_frames(brightness, times_ms):
    """The indices of the frames where the brightness jumps up by FLASH_JUMP over the frame before:
    the first frame of each flash shown."""
    first = []
    for i in range(1, len(brightness)):
        if brightness[i] - brightness[i - 1] >= FLASH_JUMP and (not first or times_ms[i] - times_ms[first[-1]] > PAUSE_MS):
            first.append(i)
    return first


def flash_onsets(brightness, times_ms):
    return [times_ms[i] for i in flash_frames(brightness, times_ms)]


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
    """`smooth`: for each marker, whether the window is judged there. Returns how many were."""
    shown = ", ".join(f"{o:+.0f}" + ("" if judged else " (not judged)") for o, judged in zip(offsets, smooth))
    print(f"site {site}: {what}: sound minus picture {shown} ms over {len(offsets)} of {markers} markers")
    if len(offsets) != markers:
        failures.append(f"site {site}: {what}: {len(offsets)} markers seen and heard, not {markers}")
        return 0
    outside = [o for o, judged in zip(offsets, smooth) if judged and not EARLIEST_MS <= o <= LATEST_MS]
    if outside:
        failures.append(f"site {site}: {what}: sound minus picture {shown} ms, outside {EARLIEST_MS:+.0f}..{LATEST_MS:+.0f}")
    return sum(smooth)


def marker_first_frames(fps):
    """The scene frame where each marker's flash begins (the clap is at its capture time)."""
    with open(SCENE) as scene:
        times_s = json.load(scene)["effects"]["av_marker"]["times_s"]
    return [math.ceil(t * fps - 1e-9) for t in times_s]


def main():
    out = sys.argv[1]
    metrics = json.load(open(f"{out}/metrics.json"))
    failures, judged, counted = [], 0, 0
    for site in "AB":
        other = "B" if site == "A" else "A"
        m = metrics["sites"][site]
        if m["scene"] != "av-marker":
            failures.append(f"site {site} played the scene {m['scene']}, not av-marker")
            continue
        claps_us = metrics["sites"][other]["sound"].get("marker_claps_us", [])
        markers = len(claps_us)
        if markers == 0:
            failures.append(f"site {other} clapped no marker: is the scene av-marker?")
            continue
        # The other site's frame F was captured F frame periods after its scene began, on the
        # clock its claps are stamped with: each clap is at its marker's first flash frame.
        frame_us = 1e6 / (SCENE_FPS * m["time_scale"])
        first = marker_first_frames(SCENE_FPS)
        epoch_us = claps_us[0] - first[0] * frame_us
        if len(first) != markers or any(abs(c - (epoch_us + f * frame_us)) > 2 for c, f in zip(claps_us, first)):
            failures.append(f"site {other}: its claps {claps_us} are not at the first frames {first} of its flashes")
            continue
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
        offsets, smooth = [], []
        for i in flash_frames(brightness, shown_ms):
            frame = frames[i].get("portrait_frame")
            heard = [c for c in claps if abs(c - shown_ms[i]) <= PAIR_MS]
            if frame is None or frame < first[0] or not heard:
                continue
            k = max(j for j in range(markers) if first[j] <= frame)
            played = min(heard, key=lambda c: abs(c - shown_ms[i]))
            captured = (epoch_us + frame * frame_us) / 1000.0
            voice, skipped, latency = played - claps_us[k] / 1000.0, captured - claps_us[k] / 1000.0, shown_ms[i] - captured
            # Steady over the half second before: at least MIN_DISPLAY_FPS pictures a second shown
            # there, none taken or shown more than two display periods after the one before, so that
            # neither frames skipped nor a stall of the picture (a loaded machine) decide the figure.
            pictures, apart = 1, 0.0
            for j in range(i, 0, -1):
                if shown_ms[i] - shown_ms[j - 1] > STEADY_MS:
                    break
                now, before = frames[j].get("portrait_frame"), frames[j - 1].get("portrait_frame")
                taken_apart = (now - before) * frame_us / 1000.0 if None not in (now, before) else math.inf
                apart = max(apart, shown_ms[j] - shown_ms[j - 1], taken_apart)
                pictures += 1
            steady = pictures >= MIN_DISPLAY_FPS * STEADY_MS / 1000.0 and apart <= 2000.0 / MIN_DISPLAY_FPS
            smooth.append(steady and latency <= MAX_PORTRAIT_LATENCY_MS)
            offsets.append(played - shown_ms[i])
            print(f"site {site}: marker {k + 1}: sound minus picture {offsets[-1]:+.0f} ms = voice latency {voice:.0f} ms - frames "
                  f"skipped {skipped:.0f} ms - portrait latency {latency:.0f} ms; {pictures} pictures in the {STEADY_MS:.0f} ms to it, "
                  f"at most {apart:.0f} ms apart (taken or shown)"
                  + ("" if smooth[-1] else ": not judged"))
        judged += judge(site, "on screen and from the loudspeakers", offsets, markers, smooth, failures)
        counted += markers
        with tempfile.TemporaryDirectory() as folder:
            decoded = decode(f"{out}/site_{site}/site.mp4", folder)
        if not decoded:
            failures.append(f"site {site}: site.mp4's picture or sound could not be decoded")
            continue
        brightness, (v_channels, v_samples) = decoded
        video_ms = [i * 1000.0 / (SCENE_FPS * m["time_scale"]) for i in range(len(brightness))]
        claps = clap_onsets(ms_energies(v_samples, v_channels))
        # The video holds each shown frame until the next: the same markers are smooth in it.
        judged += judge(site, "in site.mp4", pair(flash_onsets(brightness, video_ms), claps), markers,
                        smooth if len(smooth) == markers else [False] * markers, failures)
        counted += markers
    print(f"the window judged at {judged} of {counted} markers (both sites, on screen and in site.mp4)")
    for failure in failures:
        print("FAIL:", failure, file=sys.stderr)
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
