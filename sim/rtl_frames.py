"""A frame from `rpu render --backend rtl` (the Verilated chip) against the same frame from
`--backend functional`: the images must be equal bit for bit (OpenImageIO's idiff with
no tolerance, on the linear EXR), and the rtl backend's statistics must hold the cycle
backend's headline facts (docs/rtl.md "Chip").

    rtl_frames.py WORKDIR IDIFF -- RPU render SCENE ARGS...
"""
import json
import os
import shutil
import subprocess
import sys

work, idiff = sys.argv[1], sys.argv[2]
assert sys.argv[3] == "--"
rpu, args = sys.argv[4], sys.argv[5:]
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
failures = []


def render(backend):
    out = os.path.join(work, f"{backend}.exr")
    command = [rpu, "render", *args, "--backend", backend, "-o", out]
    if backend == "rtl":
        command += ["--stats", os.path.join(work, "rtl.json")]
    r = subprocess.run(command, capture_output=True, text=True, timeout=3600)
    print(" ".join(command), f"-> status {r.returncode}\n{r.stderr.strip()}")
    if r.returncode != 0:
        failures.append(f"{backend}: status {r.returncode}")
    return out


rtl, functional = render("rtl"), render("functional")
if not failures:
    r = subprocess.run([idiff, "-fail", "0", "-warn", "0", functional, rtl], capture_output=True, text=True)
    print(r.stdout.strip())
    if r.returncode != 0:
        failures.append(f"the rtl image differs from the functional one:\n{r.stdout}")
    with open(os.path.join(work, "rtl.json")) as f:
        stats = json.load(f)
    for key in ("cycles", "fps", "frame_seconds", "simulated_cycles_per_host_second"):
        if not stats.get(key):
            failures.append(f"rtl.json has no {key}")
    if stats.get("run", {}).get("backend") != "rtl":
        failures.append("rtl.json's run does not name the rtl backend")
    print(f"rtl: {stats.get('cycles')} cycles, {stats.get('simulated_cycles_per_host_second', 0):.0f} cycles/s")
for f in failures:
    print(f"FAIL: {f}")
sys.exit(1 if failures else 0)
