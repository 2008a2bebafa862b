#!/usr/bin/env python3
"""Writes the seed corpora of the site config, scene, Leap frame, frames.jsonl and PNG header fuzz
targets (tests/fuzz/corpus/<target>/): valid inputs and nearly valid ones, each named valid_* (the
target accepts it) or broken_* (refused). Run from anywhere; rewrites only the files it names, so
regression inputs a fuzzer found (committed by hand) stay. fuzz_corpus_<target> checks the names."""
import json
import pathlib
import struct
import zlib

root = pathlib.Path(__file__).resolve().parent / "corpus"


def write(target, name, data):
    folder = root / target
    folder.mkdir(parents=True, exist_ok=True)
    (folder / name).write_bytes(data if isinstance(data, bytes) else data.encode())


def dump(value):
    return json.dumps(value, indent=1) + "\n"


# Site config (engine/site/site_config.cpp).
full = {"scene": "clap", "site": "B", "listen": "0.0.0.0:7000", "key_file": "site.key", "time_scale": 0.25,
        "resolution_scale": 0.5, "width": 320, "height": 180, "frames": 30, "replay": "../recording", "motor": "simulated",
        "tracker": "leap:ws://127.0.0.1:6437/v6.json",
        "ibr": {"views": 4, "fusion": "avg", "carve": True, "refine": 9, "best_views": 3, "average_tolerance": 0.015,
                "edge_inset": 0.1, "portrait_supersample": 1, "blend": "ulr"},
        "hand": {"min_confidence": 0.5, "shape_adaption": "on", "appearance_smoothing": 0.1,
                 "appearance_stale_frames": 30}}
write("site_config", "valid_full.json", dump(full))
write("site_config", "valid_empty.json", "{}\n")
write("site_config", "valid_peer.json", dump({"site": "A", "peer": "10.0.0.2:7000", "tracker": "leap", "motor": "usb"}))
for name, change in [("unknown_field", {"peers": "127.0.0.1:7000"}), ("site_c", {"site": "C"}),
                     ("width_huge", {"width": 100000}), ("width_string", {"width": "320"}),
                     ("time_scale_zero", {"time_scale": 0}), ("frames_zero", {"frames": 0}),
                     ("motor_wrong", {"motor": "servo"}), ("tracker_port", {"tracker": "leap:ws://host:99999/v6.json"}),
                     ("ibr_unknown_knob", {"ibr": {"viewz": 4}}), ("ibr_views_fraction", {"ibr": {"views": 2.5}}),
                     ("hand_not_object", {"hand": [1, 2]}), ("number_overflow", None)]:
    text = dump({**full, **change}) if change else '{"width": 1E999}\n'
    write("site_config", f"broken_{name}.json", text)
# The small twin of a crash (test_knobs.cpp has the deep one): a knob's refused value was dumped
# recursively into the error, and nested a hundred thousand deep it overflowed the stack.
write("site_config", "broken_nested_knob_value.json", '{"ibr": {"views": ' + "[" * 1000 + "]" * 1000 + "}}\n")
write("site_config", "broken_not_json.json", '{"scene": "clap",\n')
write("site_config", "broken_array.json", '["scene", "clap"]\n')

# Scene (engine/sim/scene.cpp): the fuzzer writes it as scenes/fuzz.json beside a copy of assets/sites/.
assets = pathlib.Path(__file__).resolve().parents[2] / "assets"
for scene in ["clap", "noisy-clap", "wave"]:
    write("scene", f"valid_{scene}.json", (assets / "scenes" / f"{scene}.json").read_text())
clap = json.loads((assets / "scenes" / "clap.json").read_text())


def scene_with(change):
    scene = json.loads(json.dumps(clap))
    change(scene)
    return dump(scene)


for name, change in [
        ("frames_zero", lambda s: s.update(frames=0)),
        ("fps_string", lambda s: s.update(fps="30")),
        ("seed_negative", lambda s: s.update(seed=-1)),
        ("supersampling_even", lambda s: s.update(color_supersampling=2)),
        ("missing_site_file", lambda s: s["sites"]["A"].update(site="../sites/none.json")),
        ("site_c", lambda s: s["sites"].update(C=s["sites"]["A"])),
        ("skin_out_of_range", lambda s: s["sites"]["A"]["user"].update(skin_rgb=[1.5, 0.5, 0.5])),
        ("hand_scale", lambda s: s["sites"]["B"]["user"].update(hand_scale=3.0)),
        ("target_off_screen", lambda s: s["sites"]["A"]["motion"].update(touch_target_m=[5.0, 0.0])),
        ("motion_unknown", lambda s: s["sites"]["A"]["motion"].update(name="dance")),
        ("effect_unknown", lambda s: s.update(effects={"tracker_jitter": {"sigma": 1}})),
        ("effect_camera_unknown", lambda s: s.update(effects={"color_gain": {"cameras": {"side": {"gain": 1.0}}}}))]:
    write("scene", f"broken_{name}.json", scene_with(change))
write("scene", "broken_truncated.json", dump(clap)[:300])

# Leap frames (engine/sim/leap_json.cpp): one frame as the service sends it, and variants.
digits = []
for t in range(5):
    x = 10.0 * t
    digits.append({"id": 570 + t, "handId": 57, "type": t, "carpPosition": [x, 180, 40], "mcpPosition": [x + 2, 182, -20],
                   "pipPosition": [x + 2, 182, -60], "dipPosition": [x + 2, 182, -85], "btipPosition": [x + 2, 182, -105],
                   "tipPosition": [x + 2, 182, -105], "extended": True})
hand = {"id": 57, "type": "right", "confidence": 0.92, "palmPosition": [31.2, 182.4, -12.5], "palmNormal": [0.0, -1.0, 0.0],
        "direction": [0.0, 0.0, -1.0], "wrist": [28.0, 170.1, 48.0], "elbow": [20.0, 120.0, 290.0], "palmWidth": 84.9,
        "armWidth": 60, "grabStrength": 0}
frame = {"currentFrameRate": 110.2, "id": 84262, "timestamp": 3360417211, "hands": [hand], "pointables": digits,
         "gestures": [], "r": [[1, 0, 0], [0, 1, 0], [0, 0, 1]]}


def leap_with(change):
    f = json.loads(json.dumps(frame))
    change(f)
    return json.dumps(f)


write("leap_frame", "valid_device_frame.json", json.dumps(frame))
write("leap_frame", "valid_no_hands.json", '{"id": 3, "timestamp": 60000, "hands": [], "pointables": []}')
left = json.loads(json.dumps(hand))
left.update(id=58, type="left")
write("leap_frame", "valid_two_hands.json", leap_with(
    lambda f: (f["hands"].append(left), f["pointables"].extend([{**d, "id": 580 + d["type"], "handId": 58} for d in digits]))))
write("leap_frame", "valid_derived_fields.json", leap_with(
    lambda f: [f["hands"][0].pop(k) for k in ["wrist", "direction", "palmNormal", "palmPosition", "confidence", "elbow",
                                             "palmWidth", "armWidth"]]))
write("leap_frame", "valid_tip_only.json", leap_with(lambda f: [d.pop("btipPosition") for d in f["pointables"]]))
for name, change in [
        ("hand_type", lambda f: f["hands"][0].update(type="middle")),
        ("confidence", lambda f: f["hands"][0].update(confidence=1.5)),
        ("normal_not_unit", lambda f: f["hands"][0].update(palmNormal=[0, -2, 0])),
        ("vec_short", lambda f: f["pointables"][1].update(mcpPosition=[1, 2])),
        ("missing_digit", lambda f: f["pointables"].pop()),
        ("two_thumbs", lambda f: f["pointables"][1].update(type=0)),
        ("unknown_hand", lambda f: f["pointables"][0].update(handId=99)),
        ("duplicate_hand", lambda f: f["hands"].append(f["hands"][0])),
        ("no_wrist_no_carp", lambda f: (f["hands"][0].pop("wrist"), f["pointables"][2].pop("carpPosition"))),
        ("timestamp_negative", lambda f: f.update(timestamp=-1)),
        ("id_fraction", lambda f: f.update(id=1.5))]:
    write("leap_frame", f"broken_{name}.json", leap_with(change))
write("leap_frame", "broken_number_overflow.json", '{"id": 1, "timestamp": 1E999, "hands": [], "pointables": []}')
write("leap_frame", "broken_not_object.json", '[1, 2, 3]')
write("leap_frame", "broken_truncated.json", json.dumps(frame)[:200])

# frames.jsonl (engine/sim/recording.cpp): the default site's six cameras; frames 0 and 1 have images.
site = json.loads((assets / "sites" / "default.json").read_text())
names = [camera["name"] for camera in site["cameras"]]


def frame_line(index, time_us, cameras=None):
    cams = cameras if cameras is not None else [{"name": n, "timestamp_us": time_us + 100 * k} for k, n in enumerate(names)]
    return json.dumps({"frame": index, "timestamp_us": time_us, "cameras": cams})


write("frames_jsonl", "valid_two_frames.jsonl", frame_line(0, 0) + "\n" + frame_line(1, 33333) + "\n")
write("frames_jsonl", "valid_empty.jsonl", "")
write("frames_jsonl", "valid_blank_lines.jsonl", "\n" + frame_line(1, 5) + "\n\n")
write("frames_jsonl", "valid_no_camera_times.jsonl", frame_line(0, 7, [{"name": n} for n in names]) + "\n")
for name, text in [("missing_images", frame_line(2, 66666)), ("negative_time", frame_line(0, -5)),
                   ("too_few_cameras", frame_line(0, 0, [{"name": names[0]}])),
                   ("camera_not_object", frame_line(0, 0, [1] * len(names))),
                   ("camera_time_string", frame_line(0, 0, [{"timestamp_us": "0"}] * len(names))),
                   ("frame_fraction", frame_line(0, 0).replace('"frame": 0', '"frame": 0.5')),
                   ("not_object", "[0, 0]"), ("truncated", frame_line(0, 0)[:40]),
                   ("number_overflow", '{"frame": 1E999, "timestamp_us": 0, "cameras": []}'),
                   ("second_line_bad", frame_line(0, 0) + "\n{\n")]:
    write("frames_jsonl", f"broken_{name}.jsonl", text + "\n")


# PNG headers (engine/image/png_header.cpp): small real PNGs, and broken headers.
def chunk(kind, data):
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xffffffff)


def png(width, height, bit_depth, color_type, channels, ihdr_length=13, rows=None):
    ihdr = struct.pack(">IIBBBBB", width, height, bit_depth, color_type, 0, 0, 0)
    bytes_per_pixel = channels * bit_depth // 8
    raw = rows if rows is not None else b"".join(
        b"\0" + bytes((x * 37 + y * 11) % 256 for x in range(width * bytes_per_pixel)) for y in range(height))
    head = struct.pack(">I", ihdr_length) + b"IHDR" + ihdr + struct.pack(">I", zlib.crc32(b"IHDR" + ihdr) & 0xffffffff)
    return b"\x89PNG\r\n\x1a\n" + head + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b"")


write("png_header", "valid_rgba8_4x3.png", png(4, 3, 8, 6, 4))
write("png_header", "valid_rgb8_5x2.png", png(5, 2, 8, 2, 3))
write("png_header", "valid_depth16_3x3.png", png(3, 3, 16, 0, 1))
write("png_header", "valid_gray8_2x2.png", png(2, 2, 8, 0, 1))
write("png_header", "valid_header_declares_65536x65536.png", png(65536, 65536, 8, 6, 4, rows=b""))
write("png_header", "valid_rgba8_broken_data.png", png(4, 3, 8, 6, 4)[:-30])
write("png_header", "valid_rgba8_rows_missing.png", png(4, 3, 8, 6, 4, rows=b"\0" * 17))
write("png_header", "broken_too_short.png", png(4, 3, 8, 6, 4)[:20])
write("png_header", "broken_signature.png", b"\x89PNX" + png(4, 3, 8, 6, 4)[4:])
write("png_header", "broken_ihdr_length.png", png(4, 3, 8, 6, 4, ihdr_length=14))
write("png_header", "broken_zero_width.png", png(0, 3, 8, 6, 4, rows=b""))
write("png_header", "broken_jpeg.png", b"\xff\xd8\xff\xe0\x00\x10JFIF\x00" + b"\0" * 40)
write("png_header", "broken_empty.png", b"")
