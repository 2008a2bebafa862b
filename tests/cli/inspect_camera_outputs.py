#!/usr/bin/env python3
"""What `remotetouch inspect-camera` wrote for each capture with depth: depth_in_color_NNNN.png
at the colour size, covering a sane part of it with depths like the recorded ones, and
points_NNNN.ply with its exact header and one vertex per measured depth pixel, at that depth.

Usage: inspect_camera_outputs.py DIR (the --out of a run). Standard library only."""
import json
import math
import struct
import sys
import zlib
from pathlib import Path


def read_png_gray16(path):
    data = path.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", f"{path}: not a PNG"
    pos, idat, header = 8, b"", None
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    width, height, bit_depth, colour_type, _, _, interlace = header
    assert (bit_depth, colour_type, interlace) == (16, 0, 0), f"{path}: not 16-bit grey ({header})"
    raw, stride, bpp = zlib.decompress(idat), 2 * width, 2
    rows, previous = [], bytearray(stride)
    for y in range(height):
        kind, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - bpp] if i >= bpp else 0
            b, c = previous[i], previous[i - bpp] if i >= bpp else 0
            if kind == 1:
                line[i] = (line[i] + a) & 255
            elif kind == 2:
                line[i] = (line[i] + b) & 255
            elif kind == 3:
                line[i] = (line[i] + (a + b) // 2) & 255
            elif kind == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(list(struct.unpack(f">{width}H", bytes(line))))
        previous = line
    return width, height, rows


PLY_HEADER = ("ply\nformat binary_little_endian 1.0\nelement vertex {}\nproperty float x\nproperty float y\n"
              "property float z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n")

out = Path(sys.argv[1])
camera = json.loads((out / "camera.json").read_text())
color_width, color_height = camera["config"]["color_resolution"]
checked = 0
for capture in camera["captures"]:
    if capture["depth_device_us"] is None:
        continue
    n = capture["index"]
    dw, dh, depth = read_png_gray16(out / f"depth_{n:04d}.png")
    cw, ch, registered = read_png_gray16(out / f"depth_in_color_{n:04d}.png")
    assert (cw, ch) == (color_width, color_height), f"depth_in_color is {cw}x{ch}, colour {color_width}x{color_height}"
    depth_values = sorted(v for row in depth for v in row if v)
    registered_values = sorted(v for row in registered for v in row if v)
    measured, covered = len(depth_values) / (dw * dh), len(registered_values) / (cw * ch)
    median_depth = depth_values[len(depth_values) // 2]
    median_registered = registered_values[len(registered_values) // 2]
    print(f"capture {n}: depth {dw}x{dh} {measured:.3f} measured, median {median_depth} mm; "
          f"depth_in_color {cw}x{ch} {covered:.3f} covered, median {median_registered} mm")
    # A surface the colour camera sees covers its depth pixels' area scaled by the ratio of the
    # two cameras' pixels per radian squared (at about the same distance from both), less the
    # half pixel each outline loses; the colour camera's z differs from the depth camera's by the
    # small rotation and baseline between them.
    scale = camera["color"]["fx"] * camera["color"]["fy"] / (camera["depth"]["fx"] * camera["depth"]["fy"])
    ratio = len(registered_values) / (len(depth_values) * scale)
    print(f"capture {n}: covered colour pixels over measured depth pixels x {scale:.2f}: {ratio:.3f}")
    assert 0.6 < ratio < 1.2, "depth_in_color covers an area unlike the measured surface's"
    assert abs(median_registered - median_depth) < 0.05 * median_depth, "registered depths unlike the recorded ones"
    assert 0 < registered_values[0] and registered_values[-1] <= depth_values[-1] + 100

    ply = (out / f"points_{n:04d}.ply").read_bytes()
    header = PLY_HEADER.format(len(depth_values)).encode()
    assert ply.startswith(header), f"points_{n:04d}.ply: header {ply[:300]!r} is not {header!r}"
    assert len(ply) == len(header) + 15 * len(depth_values), "points: body is not 15 bytes a measured depth pixel"
    assert capture["points"] == len(depth_values), "camera.json's point count is not the measured pixels'"
    body = ply[len(header):]
    coloured = 0
    for i in range(0, len(depth_values), max(1, len(depth_values) // 2000)):
        x, y, z, r, g, b = struct.unpack_from("<fffBBB", body, 15 * i)
        assert all(math.isfinite(v) for v in (x, y, z)), f"vertex {i} is not finite"
        assert 0.1 < z < 10 and abs(x) < 2 * z and abs(y) < 2 * z, f"vertex {i} at {x, y, z}"
        coloured += (r, g, b) != (0, 0, 0)
    # The points in row order: the first is the first measured pixel, at its depth.
    first_mm = next(v for row in depth for v in row if v)
    assert abs(struct.unpack_from("<f", body, 8)[0] * 1000 - first_mm) < 0.01
    print(f"points_{n:04d}.ply: {len(depth_values)} vertices, {coloured} of the sampled ones coloured")
    assert coloured > 0, "no point took a colour"
    checked += 1
assert checked > 0, "no capture with depth"
