#!/usr/bin/python3
"""A listening `remotetouch site` under a flood of garbage connections from a stranger (no key) on
a network of its own (127.0.5.2; the rate limit counts /24 networks, and the peer's is 127.0.0.x):
while the site waits for its peer, the flood must cost it
under 30 % of a core, under 20 MB of resident memory and under 200 kB of log (stderr and
events.jsonl together); with the flood still going, the real peer (127.0.0.1) starts and is
connected within 1 s of starting to wait for it; both finish.

usage: site_under_flood.py BINARY OUT
"""
import json
import os
import secrets
import socket
import subprocess
import sys
import threading
import time

FLOOD_S = 6.0


def fail(message):
    sys.exit(f"FAIL: {message}")


def wait_for(path, text, timeout_s):
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        if os.path.exists(path) and text in open(path, errors="replace").read():
            return True
        time.sleep(0.1)
    return False


def cpu_s(pid):
    fields = open(f"/proc/{pid}/stat").read().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")  # utime + stime


def rss_mb(pid):
    for line in open(f"/proc/{pid}/status"):
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) / 1024
    return 0.0


def log_bytes(out):
    return sum(os.path.getsize(p) for p in (f"{out}/a.err", f"{out}/A/events.jsonl") if os.path.exists(p))


class Flood:
    """Threads that connect from `source`, send garbage and close, as fast as they can."""

    def __init__(self, port, source, threads=4):
        self.port, self.source, self.stop, self.connections = port, source, threading.Event(), 0
        self.lock = threading.Lock()
        self.threads = [threading.Thread(target=self.run, daemon=True) for _ in range(threads)]
        for t in self.threads:
            t.start()

    def run(self):
        garbage = os.urandom(64)
        while not self.stop.is_set():
            try:
                with socket.create_connection(("127.0.0.1", self.port), timeout=1, source_address=(self.source, 0)) as s:
                    s.sendall(garbage)
            except OSError:
                pass
            with self.lock:
                self.connections += 1

    def end(self):
        self.stop.set()
        for t in self.threads:
            t.join()


def shed(out):
    return json.load(open(f"{out}/A/metrics.json"))["net"]["connections_shed"]


def events(path):
    return [json.loads(line) for line in open(path) if line.strip()]


def main():
    binary, out = sys.argv[1], sys.argv[2]
    subprocess.run(["rm", "-rf", out], check=True)
    os.makedirs(out)
    key = f"{out}/session.key"
    with open(key, "w") as f:
        f.write(secrets.token_hex(32) + "\n")  # a hand-made key is refused as too regular
    os.chmod(key, 0o600)
    common = ["--scene", "clap", "--frames", "30", "--width", "32", "--height", "18", "--resolution-scale", "0.05",
              "--time-scale", "1", "--connect-timeout", "60", "--key-file", key]
    a = subprocess.Popen([binary, "site", "--site", "A", "--listen", "127.0.0.1:0", *common, "--out", f"{out}/A"],
                         stdout=open(f"{out}/a.out", "w"), stderr=open(f"{out}/a.err", "w"))
    try:
        if not wait_for(f"{out}/a.out", "listening on", 60):
            fail("site A never listened")
        port = int(open(f"{out}/a.out").read().split("listening on ")[1].split()[0])
        # The site looks for its user's eyes before the call: measure after that work is done.
        if not wait_for(f"{out}/a.err", "site A: eye:", 120):
            fail("site A never decided where its user's eye is")
        time.sleep(0.5)
        idle0, i0 = cpu_s(a.pid), time.monotonic()
        time.sleep(3.0)
        idle = (cpu_s(a.pid) - idle0) / (time.monotonic() - i0)
        print(f"site A waiting, no flood: {idle:.1%} of a core")
        cpu0, rss0, log0, t0 = cpu_s(a.pid), rss_mb(a.pid), log_bytes(out), time.monotonic()
        flood = Flood(port, "127.0.5.2")
        time.sleep(FLOOD_S)
        seconds = time.monotonic() - t0
        cpu = (cpu_s(a.pid) - cpu0) / seconds
        connections_timed = flood.connections
        rss_growth, log_growth = rss_mb(a.pid) - rss0, log_bytes(out) - log0
        print(f"flood: {flood.connections} connections in {seconds:.1f} s; site A used {cpu:.1%} of a core, "
              f"RSS {rss0:.1f} -> {rss0 + rss_growth:.1f} MB, log +{log_growth} bytes")

        # The real peer, while the flood goes on.
        b = subprocess.run([binary, "site", "--site", "B", "--peer", f"127.0.0.1:{port}", *common, "--out", f"{out}/B"],
                           stdout=open(f"{out}/b.out", "w"), stderr=open(f"{out}/b.err", "w"), timeout=300)
        flood.end()
        a_status = a.wait(timeout=120)
    finally:
        if a.poll() is None:
            a.kill()
    sys.stdout.write(open(f"{out}/a.err").read()[-3000:])
    if b.returncode != 0 or a_status != 0:
        fail(f"exit status A {a_status}, B {b.returncode}")
    b_events = {e["event"]: e["t_us"] for e in events(f"{out}/B/events.jsonl")}
    wait_ms = (b_events["connected"] - b_events["waiting_for_peer"]) / 1000
    print(f"the real peer connected {wait_ms:.0f} ms after it began to wait, {flood.connections} flood connections in all")
    print(f"site A shed {shed(out)} of them at accept")
    print(f"site A's CPU under the flood: {cpu:.1%} of a core, {cpu * seconds / max(1, connections_timed) * 1e6:.0f} us "
          f"per connection")
    if cpu >= 0.30:
        fail(f"the flood cost site A {cpu:.1%} of a core (limit 30 %)")
    if rss_growth >= 20:
        fail(f"site A's memory grew {rss_growth:.1f} MB under the flood (limit 20 MB)")
    if log_growth >= 200_000:
        fail(f"site A's log grew {log_growth} bytes under the flood (limit 200 kB)")
    if wait_ms > 1000:
        fail(f"the real peer waited {wait_ms:.0f} ms under the flood (limit 1 s)")
    if flood.connections < 1000:
        fail(f"only {flood.connections} flood connections: not a flood")
    print("under the flood, site A kept its memory and log bounded and let the real peer in")


if __name__ == "__main__":
    main()
