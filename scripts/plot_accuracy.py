#!/usr/bin/python3
"""Plot of `remotetouch bench accuracy --out DIR`: DIR/pareto.png, foreground PSNR against GPU ms a
frame for every configuration of DIR/results.csv, the Pareto front drawn and each point on it
labelled with its options; a second panel does the same for the hand's PSNR. The fronts are the
on_front and on_front_hand columns the command wrote. Needs Debian's python3-matplotlib."""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def label(options):
    return options.replace("--", "").strip() or "defaults"


def panel(ax, rows, accuracy, front_column, title):
    ms = [float(r["gpu_ms"]) for r in rows]
    db = [float(r[accuracy]) for r in rows]
    ax.scatter(ms, db, s=18, color="tab:gray", alpha=0.6, label="measured")
    front = sorted((r for r in rows if r[front_column] == "1"), key=lambda r: float(r["gpu_ms"]))
    fx = [float(r["gpu_ms"]) for r in front]
    fy = [float(r[accuracy]) for r in front]
    ax.step(fx, fy, where="post", color="tab:red", linewidth=1.5, label="Pareto front")
    ax.scatter(fx, fy, s=30, color="tab:red", zorder=3)
    for i, r in enumerate(front):
        ax.annotate(label(r["options"]), (fx[i], fy[i]), textcoords="offset points", xytext=(4, 4 if i % 2 else -10),
                    fontsize=7)
    # Error bars: the quartiles of the per-frame GPU ms.
    for r in rows:
        y = float(r[accuracy])
        ax.plot([float(r["gpu_ms_q1"]), float(r["gpu_ms_q3"])], [y, y], color="tab:gray", linewidth=0.6, alpha=0.6)
    ax.set_xscale("log")
    ax.set_xlabel("GPU ms a frame (median over frames, log scale; bars: quartiles)")
    ax.set_ylabel(accuracy + " (dB)")
    ax.set_title(title)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(loc="lower right", fontsize=8)


def main():
    directory = sys.argv[1]
    with open(os.path.join(directory, "results.csv"), newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        sys.exit("plot_accuracy: no rows in results.csv")
    figure, (fg, hand) = plt.subplots(1, 2, figsize=(14, 6))
    scenes = rows[0]["scenes"]
    panel(fg, rows, "psnr_fg_db", "on_front", "Foreground PSNR against GPU time (" + scenes + ")")
    panel(hand, rows, "psnr_hand_db", "on_front_hand", "Hand PSNR against GPU time (" + scenes + ")")
    figure.tight_layout()
    figure.savefig(os.path.join(directory, "pareto.png"), dpi=110)


if __name__ == "__main__":
    main()
