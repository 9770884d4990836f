#!/usr/bin/env python3
"""Several fatal signals in quick succession while an image is written: never a
temporary left beside it, and the target either the old file or the whole new image.

    signal_storm.py RPU WORKDIR TRIALS

Each trial starts a render of a large EXR, waits for its hidden temporary to appear,
then sends two or three signals drawn from SIGINT, SIGTERM and SIGHUP, a random 0-2 ms
apart (GNU timeout sends two). The process may die of any of them or finish first.
"""
import os
import random
import shutil
import signal
import subprocess
import sys
import time

from outcome import finish

rpu, work, trials = sys.argv[1], sys.argv[2], int(sys.argv[3])
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
OLD = b"the previous file\n"
target = os.path.join(work, "big.exr")
rng = random.Random(1)
failures, died, finished, missed = [], 0, 0, 0
SIGNALS = [signal.SIGINT, signal.SIGTERM, signal.SIGHUP]


def temporaries():
    return [f for f in os.listdir(work) if f.startswith(".big.exr.")]


for trial in range(trials):
    with open(target, "wb") as f:
        f.write(OLD)
    p = subprocess.Popen([rpu, "render", "tetra:1", "--width", "1024", "--height", "1024", "--spp", "1",
                          "--max-depth", "0", "-o", target], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    deadline = time.monotonic() + 60
    while p.poll() is None and not temporaries() and time.monotonic() < deadline:
        pass
    sent = []
    if p.poll() is None:
        # Somewhere in the write: up to a few ms after the temporary appeared.
        if rng.random() < 0.5:
            time.sleep(rng.uniform(0, 0.004))
        for k in range(rng.choice([2, 3])):
            sig = rng.choice(SIGNALS)
            try:
                p.send_signal(sig)
            except ProcessLookupError:
                break
            sent.append(sig.name)
            if rng.random() < 0.5:
                time.sleep(rng.uniform(0, 0.002))
    else:
        missed += 1
    status = p.wait(timeout=60)
    if status < 0:
        died += 1
    elif status == 0:
        finished += 1
    else:
        failures.append(f"trial {trial} ({', '.join(sent)}): exit status {status}")
    left = temporaries()
    if left:
        failures.append(f"trial {trial} ({', '.join(sent)}, status {status}): temporaries left: {left}")
        for t in left:
            os.remove(os.path.join(work, t))
    with open(target, "rb") as f:
        head = f.read(4)
    if status < 0 and head != OLD[:4] and head != b"\x76\x2f\x31\x01":
        failures.append(f"trial {trial}: the target is neither the old file nor an EXR")

print(f"{trials} trials: {died} died of a signal, {finished} finished first, {missed} never showed a temporary")
finish(failures, "no temporary left")
