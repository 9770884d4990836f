"""A frame from `rpu render --backend rtl` (the Verilated chip) against the same frame from
`--backend functional`: the images must be equal bit for bit (OpenImageIO's idiff with
no tolerance, on the linear EXR); the rtl backend's statistics must have every key of
the cycle backend's (but the stack pops and the speed of light, which the RTL does not
count), every unit's time must add up to the frame's cycles, and the work the RTL
counted (instructions by class, chunk issues, rays, kd nodes, leaves, triangle tests)
must equal the functional backend's (docs/chip.md "Statistics").

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
    command = [rpu, "render", *args, "--backend", backend, "-o", out, "--stats", os.path.join(work, f"{backend}.json")]
    r = subprocess.run(command, capture_output=True, text=True, timeout=3600)
    print(" ".join(command), f"-> status {r.returncode}\n{r.stderr.strip()}")
    if r.returncode != 0:
        failures.append(f"{backend}: status {r.returncode}")
    return out


def load(backend):
    with open(os.path.join(work, f"{backend}.json")) as f:
        return json.load(f)


def keys(tree, prefix=""):
    """The paths of a stats tree's leaves; a list's entries as [] (the first one's)."""
    if isinstance(tree, dict):
        return {k for name, v in tree.items() for k in keys(v, f"{prefix}.{name}" if prefix else name)}
    if isinstance(tree, list):
        return keys(tree[0], prefix + "[]") if tree else {prefix + "[]"}
    return {prefix}


def check_stats(rtl, functional, cycle):
    # The chip has no counters for a TU's pops or a ray's latency, and its units do not
    # know the triangle a ray leaves (docs/cycle-model.md "Statistics"); the speed of
    # light, the run and the configuration are the host's.
    missing = sorted(k for k in keys(cycle) - keys(rtl)
                     if not k.startswith(("speed_of_light", "run.", "config.", "ray_latency."))
                     and k not in ("traversal_units[].pops", "rays.self_hits"))
    if missing:
        failures.append(f"rtl.json lacks the cycle backend's {', '.join(missing)}")
    cycles = rtl["cycles"]
    for unit, times in (("shader_cores", ("busy", "wait_trace", "wait_memory", "wait_dependency", "idle")),
                        ("traversal_units", ("busy", "wait_memory", "wait_iu", "idle"))):
        for i, u in enumerate(rtl[unit]):
            if sum(u[t] for t in times) != cycles:
                failures.append(f"{unit}[{i}]: {' + '.join(f'{t} {u[t]}' for t in times)} != {cycles} cycles")
    for name, c in rtl["caches"].items():
        if c["hits"] + c["merged"] + c["misses"] != c["accesses"]:
            failures.append(f"caches.{name}: hits + merged + misses != accesses ({c})")
    tus = rtl["traversal_units"]
    work_pairs = [(f"instructions.by_class.{k}", rtl["instructions"]["by_class"][k], v)
                  for k, v in functional["instructions"]["by_class"].items()]
    work_pairs += [
        ("instructions.chunk_issues", rtl["instructions"]["chunk_issues"], functional["instructions"]["chunk_issues"]),
        ("rays.total", rtl["rays"]["total"], functional["rays"]["total"]),
        ("traversal nodes", sum(u["inner_nodes"] + u["leaves"] for u in tus), functional["traversal"]["nodes"]),
        ("traversal leaves", sum(u["leaves"] for u in tus), functional["traversal"]["leaves"]),
        ("triangle tests", sum(u["tests"] for u in tus), functional["traversal"]["tests"]),
        ("rays answered by the ray units", sum(u["rays"] for u in tus), functional["rays"]["total"]),
    ]
    for what, got, want in work_pairs:
        if got != want:
            failures.append(f"{what}: the rtl backend counted {got}, the functional backend {want}")


rtl, functional = render("rtl"), render("functional")
render("cycle")
if not failures:
    r = subprocess.run([idiff, "-fail", "0", "-warn", "0", functional, rtl], capture_output=True, text=True)
    print(r.stdout.strip())
    if r.returncode != 0:
        failures.append(f"the rtl image differs from the functional one:\n{r.stdout}")
    stats = load("rtl")
    check_stats(stats, load("functional"), load("cycle"))
    for key in ("cycles", "fps", "frame_seconds", "simulated_cycles_per_host_second"):
        if not stats.get(key):
            failures.append(f"rtl.json has no {key}")
    if stats.get("run", {}).get("backend") != "rtl":
        failures.append("rtl.json's run does not name the rtl backend")
    print(f"rtl: {stats.get('cycles')} cycles, {stats.get('simulated_cycles_per_host_second', 0):.0f} cycles/s")
for f in failures:
    print(f"FAIL: {f}")
sys.exit(1 if failures else 0)
