"""session_window.sh's checks: the X server's picture of the window (xwd) against the composite
site A wrote for the frame on screen, the screenshots, and site A's metrics after Esc."""
import json
import struct
import sys
from pathlib import Path

import numpy as np
from PIL import Image  # python3-pil comes with python3-matplotlib

# The window shows the composite's 8-bit values as they are (a UNORM swapchain, no scaling at the
# screen's size): at most one step apart, on all but a few pixels.
ONE_STEP = 1
MOST_PIXELS = 0.999


def read_xwd(path):
    """A ZPixmap xwd dump (X11/XWDFile.h) as an RGB array."""
    data = Path(path).read_bytes()
    header = struct.unpack(">25I", data[:100])
    header_size, _, pixmap_format = header[0], header[1], header[2]
    width, height, byte_order = header[4], header[5], header[7]
    bits_per_pixel, bytes_per_line = header[11], header[12]
    red_mask, green_mask, blue_mask = header[14], header[15], header[16]
    colors = header[19]
    assert pixmap_format == 2 and bits_per_pixel == 32, f"xwd format {pixmap_format}, {bits_per_pixel} bits per pixel"
    start = header_size + colors * 12
    rows = np.frombuffer(data[start:start + height * bytes_per_line], dtype=np.uint8).reshape(height, bytes_per_line)
    pixels = rows[:, :width * 4].copy().view("<u4" if byte_order == 0 else ">u4").reshape(height, width)

    def channel(mask):
        shift = (mask & -mask).bit_length() - 1
        return ((pixels & mask) >> shift).astype(np.uint8)

    return np.dstack([channel(red_mask), channel(green_mask), channel(blue_mask)])


def read_png(path):
    return np.asarray(Image.open(path).convert("RGB"))


def close(a, b):
    assert a.shape == b.shape, f"{a.shape} against {b.shape}"
    within = (np.abs(a.astype(int) - b.astype(int)) <= ONE_STEP).all(axis=2).mean()
    return within


out = Path(sys.argv[1])
events = [json.loads(line) for line in (out / "A" / "events.jsonl").read_text().splitlines()]
shots = [e for e in events if e["event"] == "screenshot"]
assert len(shots) == 3, shots
first, second, resized = shots
assert first["view"] == "composite" and second["view"] == "fused depth", (first["view"], second["view"])
assert first["display"] is not None, "the first screenshot names no displayed frame"

frame = read_png(out / "A" / "frames" / f"frame_{first['display']:04d}.png")
screen = read_xwd(out / "window.xwd")
shot = read_png(out / "A" / "screenshots" / first["file"])
depth_shot = read_png(out / "A" / "screenshots" / second["file"])
print("window", screen.shape, "frame", frame.shape, "displayed frame", first["display"])
screen_vs_frame = close(screen, frame)
print(f"xwd against frame_{first['display']:04d}.png: {screen_vs_frame:.4f} of pixels within one step")
assert screen_vs_frame >= MOST_PIXELS, "the window does not show the composite written for its frame"
assert close(shot, frame) >= MOST_PIXELS, "the screenshot is not the frame on screen"
differs = 1.0 - close(depth_shot, frame)
print(f"F1 (fused depth) differs from the composite on {differs:.3f} of pixels")
assert differs > 0.2, "F1 did not change the view"

assert resized["view"] == "composite" and (resized["width"], resized["height"]) == (200, 120), resized
bars = read_png(out / "A" / "screenshots" / resized["file"])
# 96x54 into 200x120 keeps its aspect at 200x112: four rows of black above and below.
assert (bars[:4] == 0).all() and (bars[-4:] == 0).all() and bars[4:-4].mean() > 20, "no bars, or no picture between them"
print("resized to 200x120: the picture keeps its aspect between black bars")

m = json.loads((out / "A" / "metrics.json").read_text())
w = m["window"]
print("site A window:", json.dumps(w))
assert m["stopped_by"] == "window" and m["display"] == "both"
assert w["presented"] >= 3 and w["screenshots"] == 3 and w["present_mode"] == "FIFO"
assert w["swapchains_made"] >= 2, "the resize made no new swapchain"
assert w["frames_held_by_pause"] >= 1, "the pause held no frame"
assert "fused depth" in w["views_seen"]
print("the window showed the composite, its debug view and quit on Esc")
