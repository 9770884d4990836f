#!/usr/bin/env python3
"""Inputs that would take the host's memory or time, and a host that refuses threads.

    input_limits.py RPU

Each must end in `rpu: error: ...` naming the input, exit status 1, within a minute and
never as an internal error (docs/robustness.md, "Files the tools read" and "Host
resources"): a scene file over its size limit, one nested deeper than any scene, one
of a million empty objects (nlohmann's callback parser took hours on it), and --threads
1000 under a limit on the address space; and a megabyte key in every kind of file that
names keys, which the message quotes in part.
"""
import os
import re
import resource
import subprocess
import sys
import tempfile

from outcome import finish

rpu = sys.argv[1]
tmp = tempfile.mkdtemp(prefix="rpu-limits-")
failures = []
MiB = 1 << 20


def run(argv, expect, label, limit_address_space=None):
    def limit():
        if limit_address_space:
            resource.setrlimit(resource.RLIMIT_AS, (limit_address_space, limit_address_space))
    try:
        r = subprocess.run(argv, capture_output=True, text=True, timeout=60, preexec_fn=limit)
    except subprocess.TimeoutExpired:
        failures.append(f"{label}: still running after 60 s")
        return
    if r.returncode != 1 or not re.search(expect, r.stderr) or "internal error" in r.stderr:
        failures.append(f"{label}: exit {r.returncode}, stderr {r.stderr.strip()[:300]!r}; expected exit 1 and /{expect}/")


def scene(name, text):
    path = os.path.join(tmp, name)
    with open(path, "w") as f:
        f.write(text)
    return path


out = os.path.join(tmp, "never.png")
big = scene("big.json", '{"comment": "' + "a" * (4 * MiB) + '"}')
run([rpu, "render", big, "-o", out], f"the scene file {re.escape(big)}: {4 * MiB + 15} bytes, more than the {4 * MiB}",
    "a scene file over 4 MiB")
deep = scene("deep.json", "[" * (4 * MiB - 64))
run([rpu, "render", deep, "-o", out], f"{re.escape(deep)}: /0/0/.*: nested deeper than 32 levels", "4 MiB of [")
objects = scene("objects.json", '{"meshes": [' + "{}," * ((4 * MiB - 32) // 3) + "{}]}")
run([rpu, "render", objects, "-o", out], f"{re.escape(objects)}: /meshes/0", "a million empty objects")
# AddressSanitizer reserves terabytes of shadow memory at start and cannot run under an
# address-space limit: under it this case is skipped, saying so (the ci preset's build
# runs it).
asan = b"__asan_init" in open(rpu, "rb").read()
if asan:
    print("SKIP --threads 1000 in 2 GiB of address space: rpu is built with AddressSanitizer")
else:
    run([rpu, "render", "tetra:1", "--backend", "functional", "--threads", "1000", "--width", "8", "--height", "8",
         "-o", out], "cannot start 1000 host threads: the host started [0-9]+ \\(Resource temporarily unavailable\\)",
        "--threads 1000 in 2 GiB of address space", limit_address_space=2 << 30)

# A key of 10^6 bytes (100 kB on the command line, which takes at most 128 kB an argument) in
# every kind of file that names keys or tokens: the message quotes 64 bytes of it.
key = "k" * 1_000_000
quoted = [
    ("scene key", [rpu, "render", scene("key.json", '{"%s": 1}' % key), "-o", out]),
    ("scene duplicate key", [rpu, "render", scene("dup.json", '{"%s": 1, "%s": 2}' % (key, key)), "-o", out]),
    ("sweep key", [rpu, "sweep", scene("key.toml", "[grid]\n%s = 1\n" % key), "-o", os.path.join(tmp, "sw")]),
    ("configuration key", [rpu, "config", "show", scene("cfg.toml", "%s = 1\n" % key)]),
    ("assembly mnemonic", [rpu, "asm", scene("key.s", "raygen:\n  %s r0\n" % key), "-o", os.path.join(tmp, "k.rfw")]),
    ("--set key", [rpu, "render", "tetra:1", "--backend", "functional", "--set", "k" * 100_000 + "=1", "-o", out]),
]
for label, argv in quoted:
    r = subprocess.run(argv, capture_output=True, text=True, timeout=60)
    if r.returncode != 1 or "... (" not in r.stderr or len(r.stderr) > 2000:
        failures.append(f"{label}: exit {r.returncode}, {len(r.stderr)} bytes of stderr: {r.stderr[:200]!r}")

finish(failures, f"{(3 if asan else 4) + len(quoted)} inputs refused within a minute, each named, huge keys quoted "
                 "in part")
