#!/usr/bin/python3
"""A soak run: `remotetouch demo` on the soak scene (a clap every 6 s at both sites) for MINUTES,
through the fault proxy, at a small size. Every two seconds it samples each site's resident
memory; at the end it reports memory over time (DIR/memory.csv), the touches each site detected
against the scene's cycles, and the portraits lost on the way.

--check fails (exit 1) unless memory stays flat after warm-up (the last quarter's median within
10 % of the second quarter's) and each site detected one touch per cycle.

usage: soak.py --binary remotetouch MINUTES [--out DIR] [--check]
"""
import argparse
import csv
import json
import os
import statistics
import subprocess
import sys
import time

CYCLE_S = 6.0  # assets/scenes/soak.json: repeat_every_s
FPS = 30


def children(pid):
    try:
        with open(f"/proc/{pid}/task/{pid}/children") as f:
            return [int(p) for p in f.read().split()]
    except OSError:
        return []


def site_of(pid):
    try:
        with open(f"/proc/{pid}/cmdline", "rb") as f:
            args = f.read().split(b"\0")
    except OSError:
        return None
    for flag, value in zip(args, args[1:]):
        if flag == b"--site":
            return value.decode()
    return None


def rss_kib(pid):
    try:
        with open(f"/proc/{pid}/status") as f:
            for line in f:
                if line.startswith("VmRSS:"):
                    return int(line.split()[1])
    except OSError:
        pass
    return None


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("minutes", type=float)
    parser.add_argument("--binary", required=True)
    parser.add_argument("--out", default="out/soak")
    parser.add_argument("--check", action="store_true")
    parser.add_argument("--delay-ms", type=int, default=20)
    parser.add_argument("--jitter-ms", type=int, default=10)
    parser.add_argument("--loss", type=float, default=0.0005, help="per record; each loss cuts the link")
    args = parser.parse_args()
    if not 0.1 <= args.minutes <= 24 * 60:
        sys.exit(f"soak: MINUTES must be between 0.1 and 1440, not {args.minutes}")

    cycles = max(1, int(args.minutes * 60 // CYCLE_S))
    frames = int(cycles * CYCLE_S * FPS)
    command = [args.binary, "demo", "--scene", "soak", "--frames", str(frames), "--width", "96", "--height", "54",
               "--resolution-scale", "0.1", "--time-scale", "1", "--display", "headless",
               "--delay-ms", str(args.delay_ms), "--jitter-ms", str(args.jitter_ms), "--loss", str(args.loss),
               "--out", args.out]
    print(f"soak: {cycles} cycles ({cycles * CYCLE_S:.0f} s of scene), delay {args.delay_ms} ms, jitter "
          f"{args.jitter_ms} ms, loss {args.loss} per record", flush=True)
    os.makedirs(args.out, exist_ok=True)
    log = open(os.path.join(args.out, "soak.log"), "w")
    demo = subprocess.Popen(command, stdout=log, stderr=subprocess.STDOUT)
    start = time.monotonic()
    samples = []  # (seconds, site, rss_kib)
    while demo.poll() is None:
        for child in children(demo.pid):
            site, rss = site_of(child), rss_kib(child)
            if site and rss:
                samples.append((time.monotonic() - start, site, rss))
        try:  # a sample every two seconds, until the demo ends (not a sample period after it)
            demo.wait(timeout=2.0)
        except subprocess.TimeoutExpired:
            pass
    log.close()
    with open(os.path.join(args.out, "memory.csv"), "w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(["seconds", "site", "rss_kib"])
        writer.writerows(samples)
    if demo.returncode != 0:
        sys.exit(f"soak: the demo failed (exit status {demo.returncode}); see {args.out}/soak.log")

    failures = []
    for site in "AB":
        rss = [s[2] for s in samples if s[1] == site]
        metrics = json.load(open(os.path.join(args.out, f"site_{site}", "metrics.json")))
        other = json.load(open(os.path.join(args.out, f"site_{'B' if site == 'A' else 'A'}", "metrics.json")))
        touch, net = metrics["touch"], metrics["net"]
        sent = other["net"]["messages_out"]["portrait"]
        received = net["messages_in"]["portrait"]
        line = (f"site {site}: touches {touch['starts']} of {cycles}, motor pulses {touch['motor_pulses']}; "
                f"portraits from the peer {received} of {sent} written ({sent - received} lost on the way); "
                f"connections lost {net['connections_lost']}, reconnects {net['reconnects']}, touches resent "
                f"{net['touches_resent']}")
        if len(rss) >= 8:
            quarter = len(rss) // 4
            warm, last = statistics.median(rss[quarter:2 * quarter]), statistics.median(rss[-quarter:])
            growth = (last - warm) / warm
            line += f"; memory {warm / 1024:.1f} MiB after warm-up, {last / 1024:.1f} MiB at the end ({growth:+.1%})"
            if args.check and growth > 0.10:
                failures.append(f"site {site}'s memory grew {growth:.1%} after warm-up")
        elif args.check:
            failures.append(f"site {site}: only {len(rss)} memory samples (run longer)")
        print(line)
        if args.check and touch["starts"] != cycles:
            failures.append(f"site {site} detected {touch['starts']} touches, the scene has {cycles}")
    print(f"written to {args.out}: memory.csv, soak.log, site_A/, site_B/")
    if failures:
        sys.exit("soak: " + "; ".join(failures))


if __name__ == "__main__":
    main()
