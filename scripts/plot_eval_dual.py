#!/usr/bin/python3
"""Plots of `remotetouch eval dual DIR`: DIR/hand_psnr.png (hand+forearm PSNR against time for each
variant, the hand's distance to the screen on a second axis, the touch phases shaded) and
DIR/sheet_<user>.png (the contact sheet: each panel beside the truth). Reads DIR/frames.csv and
DIR/sheet/sheet.json. Needs Debian's python3-matplotlib."""
import csv
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.image as mpimg  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402

PHASE_COLORS = {"far": "#dbe6f7", "approach": "#fbe3b8", "near": "#f6cccc", "touching": "#c9ebc9"}
VARIANT_STYLES = {
    "image": ("tab:blue", "-"),
    "geometry": ("tab:gray", ":"),
    "dual": ("tab:red", "-"),
    "dual_no_appearance": ("tab:orange", "--"),
    "dual_no_shape": ("tab:purple", "--"),
    "hard_switch": ("tab:green", "-."),
}


def number(text):
    return float(text) if text not in ("", None) else None


def read_frames(path):
    users = {}
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            users.setdefault(row["user"], []).append(row)
    return users


def shade_phases(ax, rows):
    """Each frame's phase over the time from halfway after the previous frame to halfway to the next."""
    points = [(number(r["t_s"]), r["phase"]) for r in rows if r["phase"] and number(r["t_s"]) is not None]
    labelled = set()
    for i, (t, phase) in enumerate(points):
        start = (points[i - 1][0] + t) / 2 if i > 0 else t
        end = (t + points[i + 1][0]) / 2 if i + 1 < len(points) else t
        label = phase if phase not in labelled else None
        labelled.add(phase)
        ax.axvspan(start, end, color=PHASE_COLORS.get(phase, "#f0f0f0"), zorder=0, label=label, lw=0)


def plot_psnr(directory, users):
    fig, axes = plt.subplots(len(users), 1, figsize=(10, 3.6 * len(users)), squeeze=False)
    for ax, (user, rows) in zip(axes[:, 0], sorted(users.items())):
        one_variant = [r for r in rows if r["variant"] == rows[0]["variant"]]
        shade_phases(ax, one_variant)
        for variant in dict.fromkeys(r["variant"] for r in rows):
            points = [(number(r["t_s"]), number(r["psnr_hand_arm_db"])) for r in rows if r["variant"] == variant]
            points = [(t, p) for t, p in points if t is not None and p is not None]
            if not points:
                continue
            color, style = VARIANT_STYLES.get(variant, ("black", "-"))
            ax.plot([t for t, _ in points], [p for _, p in points], style, color=color, label=variant, lw=1.6)
        ax.set_xlabel("scene time (s)")
        ax.set_ylabel("hand+forearm PSNR (dB)")
        ax.set_title(f"user {user} as the other site sees them")
        distance = ax.twinx()
        points = [(number(r["t_s"]), number(r["d_m"])) for r in one_variant]
        points = [(t, d) for t, d in points if t is not None and d is not None]
        distance.plot([t for t, _ in points], [d for _, d in points], color="black", lw=0.8, alpha=0.6, label="d")
        distance.set_ylabel("hand distance to the screen d (m)")
        handles, labels = ax.get_legend_handles_labels()
        ax.legend(handles, labels, fontsize=7, loc="lower left", ncol=3)
    fig.tight_layout()
    fig.savefig(os.path.join(directory, "hand_psnr.png"), dpi=110)
    plt.close(fig)


def plot_sheets(directory):
    path = os.path.join(directory, "sheet", "sheet.json")
    if not os.path.exists(path):
        return
    with open(path) as f:
        sheets = json.load(f)
    for user, panels in sheets.items():
        if not panels:
            continue
        fig, axes = plt.subplots(2, len(panels), figsize=(2.6 * len(panels), 5.4), squeeze=False)
        for column, panel in enumerate(panels):
            for row, key in enumerate(("image", "truth")):
                ax = axes[row, column]
                ax.imshow(mpimg.imread(os.path.join(directory, "sheet", panel[key])))
                ax.set_xticks([])
                ax.set_yticks([])
                if row == 0:
                    psnr = panel.get("psnr_hand_arm_db")
                    psnr_text = f", {psnr:.1f} dB" if psnr is not None else ""
                    ax.set_title(f"{panel['title']}\nd = {panel['d_m'] * 100:.0f} cm{psnr_text}", fontsize=8)
                else:
                    ax.set_title(f"truth (frame {panel['scene_frame']})", fontsize=8)
        fig.suptitle(f"user {user} as the other site sees them", fontsize=10)
        fig.tight_layout()
        fig.savefig(os.path.join(directory, f"sheet_{user}.png"), dpi=110)
        plt.close(fig)


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: plot_eval_dual.py DIR (the --out of remotetouch eval dual)")
    directory = sys.argv[1]
    frames = os.path.join(directory, "frames.csv")
    if not os.path.exists(frames):
        sys.exit(f"plot_eval_dual.py: {frames} is missing")
    users = read_frames(frames)
    if users:
        plot_psnr(directory, users)
    plot_sheets(directory)


if __name__ == "__main__":
    main()
