"""rpu fit proves its claim on three scenes, and the three configurations differ.

    test_fit.py RPU WORKDIR

For each scene: rpu fit exits 0, the table shows every parameter that can be narrowed
failing the target one step narrower (none "MEETS THE TARGET"), and the written
configuration, rendered again by `rpu render --backend cycle --config FILE --compare`,
reaches the PSNR asked for. The three fitted files must not all be the same. The --json
document (scripts/bench-record fit) holds the table's rows, says the fit is proved, and
its fitted result is within the target.
"""
import json
import os
import re
import shutil
import subprocess
import sys

rpu, work = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
SIZE = ["--width", "40", "--height", "30", "--spp", "1"]
CASES = [
    ("cornell", ["--min-psnr", "40", "--max-leaks", "0", "--isect", "watertight", "--formats", "fp32", "rpu24", "fp16"]),
    ("balls:1", ["--min-psnr", "30"]),
    ("tetra:3", ["--min-psnr", "60", "--max-slowdown", "0.25"]),
]
failures, fitted = [], {}
for scene, target in CASES:
    out = os.path.join(work, re.sub(r"\W", "_", scene) + ".toml")
    doc_file = os.path.join(work, re.sub(r"\W", "_", scene) + ".json")
    r = subprocess.run([rpu, "fit", scene, *target, *SIZE, "-o", out, "--json", doc_file], capture_output=True,
                       text=True, timeout=600)
    print(r.stdout)
    if r.returncode != 0:
        failures.append(f"{scene}: rpu fit exited {r.returncode}: {r.stderr}")
        continue
    rows = [line for line in r.stdout.splitlines()
            if re.match(r"  \S+ +\S+ +\S+ +\S+  ", line) and not line.startswith("  parameter ")]
    if len(rows) < 10:
        failures.append(f"{scene}: the proof table has {len(rows)} rows")
    for line in rows:
        if "MEETS THE TARGET" in line:
            failures.append(f"{scene}: a narrower parameter meets the target: {line}")
    with open(doc_file) as f:
        doc = json.load(f)
    table = [line.split()[:4] for line in rows]
    written = [[p["parameter"], p["base"], p["fitted"], p["narrower"] or "-"] for p in doc["parameters"]]
    if written != table:
        failures.append(f"{scene}: --json's parameters {written} are not the table's {table}")
    result, base, goal = doc["fitted_result"], doc["base_result"], doc["target"]
    if not doc["proved"]:
        failures.append(f"{scene}: --json says the fit is not proved")
    if result["psnr"] is not None and result["psnr"] < goal["min_psnr"]:
        failures.append(f"{scene}: --json's fitted PSNR {result['psnr']} is under {goal['min_psnr']}")
    if result["cycles"] > base["cycles"] * (1 + goal["max_slowdown"]):
        failures.append(f"{scene}: --json's fitted cycles {result['cycles']} are over the target")
    with open(out) as f:
        fitted[scene] = [l for l in f if not l.startswith(("name", "doc", "#"))]
    # Render with the fitted file, as a user would, against the reference.
    isect = target[target.index("--isect") + 1] if "--isect" in target else "woop"
    ref = os.path.join(work, "ref.exr")
    subprocess.run([rpu, "render", scene, *SIZE, "-o", ref], check=True, capture_output=True)
    r = subprocess.run([rpu, "render", scene, *SIZE, "--backend", "cycle", "--config", out, "--isect", isect,
                        "--compare", ref, "-o", os.path.join(work, "fitted.png")], capture_output=True, text=True)
    m = re.search(r"PSNR (\S+) dB", r.stderr)
    psnr = float(m.group(1)) if m else None
    if psnr is None or psnr < float(target[target.index("--min-psnr") + 1]):
        failures.append(f"{scene}: the fitted configuration renders at {psnr} dB: {r.stderr}")
if len(fitted) == 3 and len({"".join(v) for v in fitted.values()}) < 3:
    failures.append("two scenes got the same configuration")
for f in failures:
    print("FAIL:", f)
sys.exit(1 if failures else 0)
