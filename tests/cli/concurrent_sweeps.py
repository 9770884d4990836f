#!/usr/bin/env python3
"""Two runs on one sweep directory (docs/sweeps.md, "Running"): a second `rpu sweep` is
refused at once while the first goes on to its table; a killed one leaves no lock behind;
two `rpu sweep-point` runs of one point take turns and both succeed.

    concurrent_sweeps.py RPU SWEEP_FILE WORKDIR
"""
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import time

from outcome import finish

rpu, spec, work = sys.argv[1], sys.argv[2], sys.argv[3]
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
failures = []


def wait_for(path, process, seconds=60):
    deadline = time.monotonic() + seconds
    while not os.path.exists(path) and process.poll() is None and time.monotonic() < deadline:
        time.sleep(0.01)
    return os.path.exists(path)


# 1. A second rpu sweep while the first runs.
d = os.path.join(work, "both")
first = subprocess.Popen([rpu, "sweep", spec, "-o", d], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
if not wait_for(os.path.join(d, "plan.json"), first):
    failures.append("the first sweep never wrote its plan")
start = time.monotonic()
second = subprocess.run([rpu, "sweep", spec, "-o", d], capture_output=True, text=True, timeout=60)
waited = time.monotonic() - start
out, err = first.communicate(timeout=600)
if first.returncode != 0 or not os.path.exists(os.path.join(d, "sweep.csv")):
    failures.append(f"the first sweep: status {first.returncode}, sweep.csv {'written' if os.path.exists(os.path.join(d, 'sweep.csv')) else 'missing'}: {err[-500:]}")
expect = f"rpu: error: -o {re.escape(d)}: another rpu sweep \\(pid {first.pid}\\) is running on this directory"
if second.returncode != 1 or not re.search(expect, second.stderr):
    failures.append(f"the second sweep: status {second.returncode}, stderr {second.stderr.strip()[:300]!r}; expected 1 and /{expect}/")
elif waited > 10:
    failures.append(f"the second sweep was refused after {waited:.1f} s, not at once")

# 2. A killed sweep leaves nothing that stops the next.
d = os.path.join(work, "killed")
killed = subprocess.Popen([rpu, "sweep", spec, "-o", d], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
wait_for(os.path.join(d, "plan.json"), killed)
killed.send_signal(signal.SIGKILL)
killed.wait()
again = subprocess.run([rpu, "sweep", spec, "-o", d], capture_output=True, text=True, timeout=600)
if again.returncode != 0 or not os.path.exists(os.path.join(d, "sweep.csv")):
    failures.append(f"a sweep after a killed one: status {again.returncode}: {again.stderr[-500:]}")

# 3. One point run twice at once: both succeed, the point is rendered once, its record whole.
d = os.path.join(work, "point")
subprocess.run([rpu, "sweep", spec, "-o", d, "--plan"], check=True, capture_output=True)
with open(os.path.join(d, "plan.json")) as f:
    reference = json.load(f)["references"][0]["id"]
runs = [subprocess.Popen([rpu, "sweep-point", d, reference], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        for _ in range(2)]
results = [(r.wait(timeout=300), r.stdout.read(), r.stderr.read()) for r in runs]
if any(status != 0 for status, _, _ in results):
    failures.append(f"one point run twice at once: {[(s, e[-300:]) for s, _, e in results]}")
elif sum("done already" in o for _, o, _ in results) != 1:
    failures.append(f"one point run twice at once: expected one run to find it done: {[o for _, o, _ in results]}")
with open(os.path.join(d, "points", reference + ".json")) as f:
    if json.load(f).get("id") != reference:
        failures.append("one point run twice at once: its record is not its own")

finish(failures, "the second sweep refused at once, a killed one no obstacle, a point run twice rendered once")
