#!/usr/bin/env python3
"""Every command line README.md shows, run as a user would (the slow ones shortened), and every
command its table names: fails when a documented command, option or output file is gone, or a
row of the demo's table that docs/reading-the-demo.md explains.
    readme_commands.py README BINARY OUT
"""
import os
import re
import shlex
import socket
import stat
import subprocess
import sys
import time

readme, binary, out = sys.argv[1], os.path.abspath(sys.argv[2]), os.path.abspath(sys.argv[3])
text = open(readme).read()
demo_rows_doc = os.path.join(os.path.dirname(os.path.abspath(readme)), "docs", "reading-the-demo.md")
demo_rows_text = open(demo_rows_doc).read() if os.path.exists(demo_rows_doc) else ""
failures = []
# Small and short: the same code paths as the README's lines, in seconds instead of minutes.
SHORT = ["--frames", "12", "--width", "64", "--height", "36", "--resolution-scale", "0.05"]


def fail(message):
    failures.append(message)
    print("FAIL:", message, file=sys.stderr)


def run(args, cwd, timeout=300, **kw):
    return subprocess.run([binary] + args, cwd=cwd, capture_output=True, text=True, timeout=timeout, **kw)


def help_text(words):
    # CLI11 answers --help before it looks at the words: ask the parent whether it has the command.
    if words:
        listed = run(words[:-1] + ["--help"], out).stdout
        if not re.search(r"^\s+" + re.escape(words[-1]) + r"\s", listed, re.M):
            fail(f"remotetouch {' '.join(words)}: no such command (the README names it)")
    result = run(words + ["--help"], out)
    if result.returncode != 0:
        fail(f"remotetouch {' '.join(words)} --help exited with {result.returncode}")
    return result.stdout


def command_words(args):
    """The command and subcommand words at the front of args (e.g. ["bench", "ibr"])."""
    words = []
    for arg in args:
        if arg.startswith("-") or (words and words[0] not in ("bench", "eval", "calibrate", "export")) or len(words) == 2:
            break
        words.append(arg)
    return words


def check_options(args):
    """Each option the line gives is one the command documents in its --help."""
    words = command_words(args)
    documented = set(re.findall(r"(--[a-z][a-z0-9-]*)", help_text(words)))
    for arg in args[len(words):]:
        if arg.startswith("--") and arg.split("=")[0] not in documented:
            fail(f"remotetouch {' '.join(words)} has no option {arg} (the README uses it)")
    return words


# The lines of the README's shell blocks that run remotetouch, comments dropped.
lines = []
for block in re.findall(r"```sh\n(.*?)```", text, re.S):
    for line in block.splitlines():
        line = line.split("#")[0].strip()
        parts = shlex.split(line)
        if parts and re.fullmatch(r"(scripts/|build/)?remotetouch", parts[0]):
            lines.append(parts[1:])
print(f"{len(lines)} command lines in the README's examples")
os.makedirs(out, exist_ok=True)

# Every command in the table of commands has its --help.
table = re.search(r"\| command \| what it does \|\n\|---\|---\|\n((?:\|.*\n)+)", text)
if not table:
    fail("the README's table of commands is gone")
else:
    for row in table.group(1).splitlines():
        names = re.findall(r"`([^`]+)`", row.split("|")[1])
        group = None
        for name in names:
            words = name.split()
            if len(words) == 2 and words[0] in ("bench", "eval", "calibrate", "export"):
                group = words[0]
            elif group:
                words = [group] + words
            help_text([w for w in words if re.fullmatch(r"[a-z][a-z-]*", w)])

ran = set()
for args in lines:
    words = check_options(args)
    kind = words[0] if words else ""
    if kind == "keygen":
        # As shown: a key only its owner reads, and never written over.
        key = os.path.join(out, args[1])
        if os.path.exists(key):
            os.remove(key)
        first, second = run(args, out), run(args, out)
        mode = stat.S_IMODE(os.stat(key).st_mode) if os.path.exists(key) else None
        if first.returncode != 0 or mode != 0o600:
            fail(f"keygen: exit {first.returncode}, mode {oct(mode) if mode else 'no file'}")
        if second.returncode == 0 or "never overwritten" not in second.stderr:
            fail("keygen wrote over an existing key file")
        ran.add("keygen")
    elif kind == "demo":
        result = run(args + SHORT + ["--display", "headless"], out)
        if result.returncode != 0:
            fail(f"demo exited with {result.returncode}: {result.stderr[-2000:]}")
        for path in ["site_A/frames/frame_0000.png", "site_A/site.mp4", "site_A/metrics.json", "site_B/metrics.json",
                     "events.jsonl", "metrics.json"]:
            if not os.path.exists(os.path.join(out, "out/demo", path)):
                fail(f"demo wrote no out/demo/{path}, which the README promises")
        rows = re.search(r"\| row \| what it says \|\n\|---\|---\|\n((?:\|.*\n)+)", demo_rows_text)
        for row in rows.group(1).splitlines() if rows else fail(f"{demo_rows_doc} has no table of the demo's rows") or []:
            name = re.findall(r"`([^`]+)`", row.split("|")[1])[0]
            if name not in result.stdout:
                fail(f"the demo's table has no row '{name}', which docs/reading-the-demo.md explains")
        ran.add("demo")
# A replay needs its recording, a live site its cameras: neither is on a test machine.
ran_sites = [a for a in lines if command_words(a) == ["site"] and "--replay" not in a and "--site-file" not in a]
if len(ran_sites) == 2:
    # Two sites by hand on loopback, on a free port in place of the README's.
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        port = str(probe.getsockname()[1])
    sites = [[arg.replace(":7000", ":" + port) for arg in a] + SHORT + ["--display", "headless"] for a in ran_sites]
    listener = subprocess.Popen([binary] + sites[0], cwd=out, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    time.sleep(0.5)
    connector = run(sites[1], out)
    listener_out, listener_err = listener.communicate(timeout=300)
    for name, code, stdout, stderr in [("A", listener.returncode, listener_out, listener_err),
                                       ("B", connector.returncode, connector.stdout, connector.stderr)]:
        if code != 0:
            fail(f"site {name} by hand exited with {code}: {stderr[-2000:]}")
        if not os.path.exists(os.path.join(out, f"out/site_{name}/metrics.json")):
            fail(f"site {name} wrote no out/site_{name}/metrics.json, which the README promises")
        if "frames displayed" not in stdout:
            fail(f"site {name} ended without its table")
    ran.add("site")
else:
    fail(f"the README shows {len(ran_sites)} site lines to run by hand, expected the two of site A and B")
for kind in ("keygen", "demo", "site"):
    if kind not in ran:
        fail(f"no README line ran {kind}")
if failures:
    sys.exit(1)
print("every README command line ran:", ", ".join(sorted(ran)))
