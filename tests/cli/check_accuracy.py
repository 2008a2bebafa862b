#!/usr/bin/python3
"""Checks the outputs of `remotetouch bench accuracy --out DIR`: results.csv has one row per
configuration (no options twice, the expected count) with finite psnr_fg_db and gpu_ms; pareto.png
is a PNG of a plausible size; the front is right: every row marked on it is beaten by no other row
in both accuracy and time, every row off it is beaten by one, and pareto.md lists exactly those rows.
Usage: check_accuracy.py DIR EXPECTED_ROWS"""
import csv
import math
import os
import struct
import sys


def fail(message):
    sys.exit("check_accuracy: " + message)


def beats(a, b, accuracy):
    """a is as accurate and as fast as b, and better in one."""
    aa, am, ba, bm = float(a[accuracy]), float(a["gpu_ms"]), float(b[accuracy]), float(b["gpu_ms"])
    return aa >= ba and am <= bm and (aa > ba or am < bm)


def check_front(rows, accuracy, column):
    for row in rows:
        beaten_by = [other["options"] for other in rows if other is not row and beats(other, row, accuracy)]
        if row[column] == "1" and beaten_by:
            fail(f"'{row['options']}' is on the {accuracy} front but '{beaten_by[0]}' beats it")
        if row[column] == "0" and not beaten_by:
            fail(f"'{row['options']}' is beaten by no row but not on the {accuracy} front")
        if row[column] not in ("0", "1"):
            fail(f"{column} of '{row['options']}' is '{row[column]}'")


def main():
    directory, expected = sys.argv[1], int(sys.argv[2])
    with open(os.path.join(directory, "results.csv"), newline="") as f:
        reader = csv.DictReader(f)
        for column in ("options", "psnr_fg_db", "psnr_hand_db", "depth_mae_edge_mm", "alpha_iou", "gpu_ms",
                       "gpu_ms_q1", "gpu_ms_q3", "on_front", "on_front_hand"):
            if column not in reader.fieldnames:
                fail(f"results.csv lacks the column {column}")
        rows = list(reader)
    if len(rows) != expected:
        fail(f"results.csv has {len(rows)} rows, expected {expected}")
    if len({row["options"] for row in rows}) != len(rows):
        fail("a configuration appears twice in results.csv")
    for row in rows:
        for column in ("psnr_fg_db", "psnr_hand_db", "depth_mae_edge_mm", "alpha_iou", "gpu_ms"):
            value = float(row[column])
            if not math.isfinite(value):
                fail(f"{column} of '{row['options']}' is {value}")
        if float(row["gpu_ms"]) <= 0:
            fail(f"gpu_ms of '{row['options']}' is not positive")
        if not float(row["gpu_ms_q1"]) <= float(row["gpu_ms"]) <= float(row["gpu_ms_q3"]):
            fail(f"the median GPU ms of '{row['options']}' lies outside its quartiles")
    check_front(rows, "psnr_fg_db", "on_front")
    check_front(rows, "psnr_hand_db", "on_front_hand")

    with open(os.path.join(directory, "pareto.png"), "rb") as f:
        head = f.read(24)
    if head[:8] != b"\x89PNG\r\n\x1a\n":
        fail("pareto.png is not a PNG")
    width, height = struct.unpack(">II", head[16:24])
    if width < 600 or height < 300:
        fail(f"pareto.png is {width}x{height}, too small for two panels")

    with open(os.path.join(directory, "pareto.md")) as f:
        text = f.read()
    if "Command: `remotetouch bench accuracy" not in text:
        fail("pareto.md does not name the command that made it")
    listed = []
    for line in text.splitlines():
        if line.startswith("| ") and not line.startswith("| options"):
            cell = line.split(" | ")[0][2:]
            listed.append("" if cell == "the defaults" else cell.strip("`"))
    front = sorted(row["options"] for row in rows if row["on_front"] == "1")
    if sorted(listed) != front:
        fail(f"pareto.md lists {sorted(listed)}, the front is {front}")
    print(f"check_accuracy: {len(rows)} rows, {len(front)} on the front, pareto.png {width}x{height}: ok")


if __name__ == "__main__":
    main()
