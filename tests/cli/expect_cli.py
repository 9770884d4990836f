"""Runs the rpu CLI and checks its exit status, what it prints and the image it writes.

    expect_cli.py --status N [--stderr REGEX]... [--stdout REGEX]... [--png PATH WxH]
                  [--file PATH REGEX]... [--copy SRC DST]... [--old-file PATH SRC]...
                  [--fsize-limit BYTES] [--timeout SECONDS] -- rpu ARGS...

--copy copies SRC to DST before the run. --old-file does too, and afterwards PATH must
hold SRC's bytes still, with no temporary of it (".NAME.*") left beside it.
--fsize-limit sets RLIMIT_FSIZE in the child: a full disk without root.
"""
import argparse
import os
import re
import resource
import shutil
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
ap.add_argument("--copy", nargs=2, action="append", default=[], metavar=("SRC", "DST"),
                help="file to copy before the run")
ap.add_argument("--old-file", nargs=2, action="append", default=[], metavar=("PATH", "SRC"),
                help="PATH holds SRC's bytes before the run and must still hold them after it")
ap.add_argument("--fsize-limit", type=int, help="RLIMIT_FSIZE of the command, in bytes")
ap.add_argument("--timeout", type=float, default=300, help="seconds the command may take")
ap.add_argument("command", nargs=argparse.REMAINDER)
args = ap.parse_args()
command = args.command[1:] if args.command[:1] == ["--"] else args.command

for src, dst in args.copy + [(src, path) for path, src in args.old_file]:
    shutil.copyfile(src, dst)


def limit_file_size():
    resource.setrlimit(resource.RLIMIT_FSIZE, (args.fsize_limit, resource.RLIM_INFINITY))


failures = []
try:
    r = subprocess.run(command, capture_output=True, text=True, timeout=args.timeout,
                       preexec_fn=limit_file_size if args.fsize_limit is not None else None)
except subprocess.TimeoutExpired:
    print(f"$ {' '.join(command)}\nFAIL: still running after {args.timeout} s")
    sys.exit(1)
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
for path, src in args.old_file:
    with open(path, "rb") as a, open(src, "rb") as b:
        if a.read() != b.read():
            failures.append(f"{path} changed: it no longer holds the bytes of {src}")
    directory, name = os.path.split(os.path.abspath(path))
    left = [f for f in os.listdir(directory) if f.startswith(f".{name}.")]
    if left:
        failures.append(f"temporaries left beside {path}: {left}")
print(f"$ {' '.join(command)}\nstatus {r.returncode}\n--- stdout ---\n{r.stdout}\n--- stderr ---\n{r.stderr}")
for f in failures:
    print(f"FAIL: {f}")
sys.exit(1 if failures else 0)
