#!/usr/bin/env python3
"""The touch's sound in a two-site demo, listened to in each site's audio.wav.

    check_touch_sound.py OUT TOUCHES

Each site must have played exactly TOUCHES touch sounds (none withdrawn among them), each asked
for at the moment its vibration is felt (a pulse given ahead of a predicted contact: the motor's
latency after the command; else the command itself, at the touch start), and each must be heard in
audio.wav there: its onset, found in the file's own samples (where the two channels first differ,
for a sound placed off the middle), within ONSET_TOLERANCE_MS of the sample the site placed it
at, and that placement within ONSET_TOLERANCE_MS of the moment asked for. Where no touch happened, the file must hold no touch sound.

site.mp4 (at the scene's pace on the wall's clock) must carry the same sound: decoded from it, each
touch sound's onset within VIDEO_TOLERANCE_MS of its moment on the video's clock (its first frame
shown at frames.jsonl's first t_us).
"""
import array
import json
import math
import os
import subprocess
import sys
import tempfile
import wave

ONSET_TOLERANCE_MS = 10.0
RATE = 48000
WINDOW = RATE // 1000          # 1 ms of energy
BEFORE = 5 * WINDOW            # against the 5 ms before it
JUMP_DB, FLOOR_DB = 10.0, -30.0
SEARCH = RATE // 50            # 20 ms either side of the moment asked for
# Matched millisecond by millisecond, through a lossy codec.
VIDEO_TOLERANCE_MS = 10
LOUDNESS_CORRELATION = 0.8
SIDE_THRESHOLD = 2             # of 32768: the same voice rounds alike in both channels


def energy(samples, channels, begin, end):
    total = 0.0
    for i in range(begin * channels, end * channels):
        total += (samples[i] / 32768.0) ** 2
    return total / max(1, (end - begin) * channels)


def onset_near(samples, channels, frames, expected):
    """The millisecond near `expected` whose energy jumps most over the 5 ms before it, if it jumps
    by JUMP_DB to above FLOOR_DB: right where nothing else plays."""
    best, best_jump = None, 10 ** (JUMP_DB / 10)
    for start in range(max(BEFORE, expected - SEARCH), min(frames - WINDOW, expected + SEARCH), WINDOW // 4):
        now = energy(samples, channels, start, start + WINDOW)
        before = energy(samples, channels, start - BEFORE, start)
        jump = now / max(before, 1e-12)
        if 10 * math.log10(now + 1e-12) >= FLOOR_DB and jump > best_jump:
            best, best_jump = start, jump
    return best


def side_onset_near(samples, frames, expected):
    """The first sample near `expected` where left and right differ: the far voice plays the same
    from both loudspeakers and cancels out of their difference, a sound placed off the middle does
    not (by its level and its time difference)."""
    for i in range(max(0, expected - SEARCH), min(frames, expected + SEARCH)):
        if abs(samples[2 * i] - samples[2 * i + 1]) > SIDE_THRESHOLD:
            return i
    return None


def envelope(samples, channels, first_ms, end_ms):
    """Energy of each millisecond in [first_ms, end_ms); zero outside the samples."""
    frames = len(samples) // channels
    out = []
    for ms in range(first_ms, end_ms):
        begin, end = ms * WINDOW, (ms + 1) * WINDOW
        out.append(energy(samples, channels, begin, end) if begin >= 0 and end <= frames else 0.0)
    return out


def correlation(a, b):
    n = len(a)
    ma, mb = sum(a) / n, sum(b) / n
    num = sum((x - ma) * (y - mb) for x, y in zip(a, b))
    den = math.sqrt(sum((x - ma) ** 2 for x in a) * sum((y - mb) ** 2 for y in b))
    return num / den if den > 0 else 0.0


def read_stereo(path):
    with wave.open(path) as wav:
        channels, frames = wav.getnchannels(), wav.getnframes()
        return channels, frames, array.array("h", wav.readframes(frames))


def sound_of_video(video):
    """site.mp4's sound track, decoded to a temporary WAV; None when it has none."""
    with tempfile.TemporaryDirectory() as folder:
        wav = os.path.join(folder, "sound.wav")
        run = subprocess.run(["gst-launch-1.0", "-q", "filesrc", f"location={video}", "!", "qtdemux", "name=d", "d.audio_0",
                              "!", "queue", "!", "avdec_aac", "!", "audioconvert", "!", "audio/x-raw,format=S16LE,channels=2",
                              "!", "wavenc", "!", "filesink", f"location={wav}"], capture_output=True, text=True, timeout=120)
        if run.returncode != 0 or not os.path.exists(wav):
            return None
        return read_stereo(wav)


def main():
    out, touches = sys.argv[1], int(sys.argv[2])
    metrics = json.load(open(f"{out}/metrics.json"))
    events = [json.loads(line) for line in open(f"{out}/events.jsonl")]
    for site in "AB":
        sound = metrics["sites"][site]["sound"]
        latency_ms = metrics["sites"][site]["touch"]["settings"]["motor_latency_ms"]
        played = [s for s in sound["touch_sounds"]["sounds"] if not s["cancelled"]]
        assert len(played) == touches, (site, sound["touch_sounds"])
        asked = [e for e in events if e["event"] == "touch_sound" and e["site"] == site]
        pulses = [e["t_us"] for e in events if e["event"] == "motor_pulse" and e["site"] == site]
        for event in asked:
            lead_ms = (event["onset_us"] - event["t_us"]) / 1000
            assert event["t_us"] in pulses, ("a touch sound without its pulse", event)
            assert abs(lead_ms) < 0.01 or abs(lead_ms - latency_ms) < 0.01, ("asked for neither at the vibration nor now", event)
        channels, frames, samples = read_stereo(f"{out}/site_{site}/audio.wav")
        assert channels == 2, f"site {site}: audio.wav has {channels} channels, not the stereo pair"
        start_us = sound["audio_wav"]["start_us"]
        for s in played:
            # Where the sound thread put it: the file's samples run on without the time a stalled
            # thread gave up (its late ticks), so its clock can fall behind the wall's.
            expected = s["onset_sample"]
            # Off the middle, the side signal holds the sound alone; in the middle, its onset must
            # stand out of whatever else plays.
            off_middle = abs(s["gain_left"] - s["gain_right"]) > 0.005
            found = side_onset_near(samples, frames, expected) if off_middle else onset_near(samples, channels, frames, expected)
            assert found is not None, f"site {site}: no touch sound heard near {expected / RATE:.3f} s of audio.wav"
            off_ms = (found - expected) * 1000 / RATE
            print(f"site {site}: {s['sound']} heard {off_ms:+.1f} ms from its vibration (asked {s['late_ms']:+.2f} ms late), "
                  f"azimuth {s['azimuth_deg']:+.1f} deg")
            assert abs(off_ms) <= ONSET_TOLERANCE_MS, (site, off_ms)
            assert abs(s["late_ms"]) <= ONSET_TOLERANCE_MS, (site, s)
        muxed = [e for e in events if e["event"] == "sound_in_video" and e["site"] == site]
        assert muxed and muxed[0]["muxed"], f"site {site}: site.mp4 has no sound: {muxed}"
        decoded = sound_of_video(f"{out}/site_{site}/site.mp4")
        assert decoded, f"site {site}: no sound track could be decoded from site.mp4"
        with open(f"{out}/site_{site}/frames.jsonl") as lines:
            video_start_us = json.loads(lines.readline())["t_us"]
        v_channels, v_frames, v_samples = decoded
        assert v_channels == 2, f"site {site}: site.mp4's sound has {v_channels} channels"
        # Coded sound is not the same sample for sample: match the loudness, millisecond by
        # millisecond, of the half second around each touch sound in audio.wav against site.mp4's.
        for s in played:
            in_wav = s["onset_sample"] // WINDOW
            in_video = (s["onset_sample"] - round((video_start_us - start_us) * RATE / 1e6)) // WINDOW
            reference = envelope(samples, channels, in_wav - 200, in_wav + 300)
            best_lag, best = None, -1.0
            for lag in range(-100, 101):
                c = correlation(reference, envelope(v_samples, v_channels, in_video - 200 + lag, in_video + 300 + lag))
                if c > best:
                    best_lag, best = lag, c
            print(f"site {site}: {s['sound']} heard in site.mp4 {best_lag:+d} ms from its moment on the video's clock "
                  f"(loudness correlation {best:.3f})")
            assert best >= LOUDNESS_CORRELATION and abs(best_lag) <= VIDEO_TOLERANCE_MS, (site, best_lag, best)
    print("touch sounds ok")


if __name__ == "__main__":
    main()
