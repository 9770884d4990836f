"""Runs the rpu CLI and checks its exit status, what it prints and the image it writes.

    expect_cli.py --status N [--stderr REGEX]... [--stdout REGEX]... [--png PATH WxH]
                  [--file PATH REGEX]... -- rpu ARGS...
"""
import argparse
import re
import struct
import subprocess
import sys

ap = argparse.ArgumentParser()
ap.add_argument("--status", type=int, required=True)
ap.add_argument("--stderr", action="append", default=[], help="regex stderr must match")
ap.add_argument("--stdout", action="append", default=[], help="regex stdout must match")
ap.add_argument("--png", nargs=2, metavar=("PATH", "WxH"), help="PNG that must exist with this size")
ap.add_argument("--file", nargs=2, action="append", default=[], metavar=("PATH", "REGEX"),
                help="text file the command writes, which must match REGEX")
ap.add_argument("command", nargs=argparse.REMAINDER)
args = ap.parse_args()
command = args.command[1:] if args.command[:1] == ["--"] else args.command

r = subprocess.run(command, capture_output=True, text=True, timeout=300)
failures = []
if r.returncode != args.status:
    failures.append(f"exit status {r.returncode}, expected {args.status}")
for stream, patterns, text in (("stderr", args.stderr, r.stderr), ("stdout", args.stdout, r.stdout)):
    for pattern in patterns:
        if not re.search(pattern, text, re.S):
            failures.append(f"{stream} does not match /{pattern}/")
if args.png:
    path, size = args.png
    try:
        with open(path, "rb") as f:
            head = f.read(24)
        if head[:8] != b"\x89PNG\r\n\x1a\n":
            failures.append(f"{path} is not a PNG")
        else:
            w, h = struct.unpack(">II", head[16:24])
            if f"{w}x{h}" != size:
                failures.append(f"{path} is {w}x{h}, expected {size}")
    except OSError as e:
        failures.append(f"{path}: {e}")
for path, pattern in args.file:
    try:
        with open(path, encoding="utf-8") as f:
            text = f.read()
        if not re.search(pattern, text, re.S):
            failures.append(f"{path} does not match /{pattern}/:\n{text}")
    except OSError as e:
        failures.append(f"{path}: {e}")
print(f"$ {' '.join(command)}\nstatus {r.returncode}\n--- stdout ---\n{r.stdout}\n--- stderr ---\n{r.stderr}")
for f in failures:
    print(f"FAIL: {f}")
sys.exit(1 if failures else 0)
