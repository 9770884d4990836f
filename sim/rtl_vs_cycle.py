#!/usr/bin/env python3
"""Frames on the rtl backend against the cycle backend: cycles of each, their ratio, and
how fast the Verilated chip runs. Appends one record per frame to
bench/results/rtl_frames.json (docs/chip.md "Measured"; scripts/doc-tables renders it).

    sim/rtl_vs_cycle.py [--rpu build/release/rpu] [--config tiny --config default ...]
                        [--scene cornell ...] [--size 16x12] [--spp 4] [--max-depth 2]
                        [--dry-run]
"""
import argparse
import datetime
import json
import os
import pathlib
import subprocess
import sys
import tempfile

ROOT = pathlib.Path(__file__).resolve().parent.parent
RESULTS = ROOT / "bench" / "results" / "rtl_frames.json"
DESCRIPTION = ("Frames on the rtl backend (the Verilated chip) against the cycle backend: modelled cycles of each "
               "and the rtl backend's host speed, one host thread")


def render(rpu, backend, scene, args, work):
    stats = os.path.join(work, f"{backend}.json")
    command = [rpu, "render", scene, "--backend", backend, *args, "-o", os.path.join(work, f"{backend}.png"),
               "--stats", stats]
    r = subprocess.run(command, capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"rtl_vs_cycle: {' '.join(command)} failed ({r.returncode}):\n{r.stderr}")
    with open(stats) as f:
        return json.load(f)


def share(stats, units, counter):
    total = sum(u[counter] for u in stats[units])
    return total / (stats["cycles"] * len(stats[units]))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--rpu", default=str(ROOT / "build" / "release" / "rpu"))
    ap.add_argument("--config", action="append", help="named configuration (repeatable; default tiny, default, rpu2005)")
    ap.add_argument("--scene", action="append", help="scene (repeatable; default cornell, balls:1)")
    ap.add_argument("--size", default="16x12")
    ap.add_argument("--spp", default="4")
    ap.add_argument("--max-depth", default="2")
    ap.add_argument("--dry-run", action="store_true", help="print the records, do not append them")
    o = ap.parse_args()
    width, height = o.size.split("x")
    commit = subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--short=7", "HEAD"], capture_output=True,
                            text=True, check=True).stdout.strip()
    records = []
    for config in o.config or ["tiny", "default", "rpu2005"]:
        for scene in o.scene or ["cornell", "balls:1"]:
            args = ["--config", config, "--width", width, "--height", height, "--spp", o.spp,
                    "--max-depth", o.max_depth]
            with tempfile.TemporaryDirectory() as work:
                rtl = render(o.rpu, "rtl", scene, args, work)
                cycle = render(o.rpu, "cycle", scene, args, work)
            frame = f"{scene} {o.size}, {o.spp} spp, depth {o.max_depth}"
            record = {
                "commit": commit, "date": datetime.date.today().isoformat(),
                "command": f"sim/rtl_vs_cycle.py --config {config} --scene {scene} --size {o.size} --spp {o.spp} "
                           f"--max-depth {o.max_depth}",
                "config": config, "frame": frame,
                "rtl_cycles": rtl["cycles"], "cycle_cycles": cycle["cycles"],
                "rtl_host_s": round(rtl["host_seconds"], 2),
                "rtl_cycles_per_s": round(rtl["simulated_cycles_per_host_second"]),
                "rtl_core_busy": round(share(rtl, "shader_cores", "busy"), 3),
                "cycle_core_busy": round(share(cycle, "shader_cores", "busy"), 3),
                "rtl_core_wait_trace": round(share(rtl, "shader_cores", "wait_trace"), 3),
                "cycle_core_wait_trace": round(share(cycle, "shader_cores", "wait_trace"), 3),
            }
            print(json.dumps(record), flush=True)
            records.append(record)
    if o.dry_run:
        return
    data = {"description": DESCRIPTION, "records": []}
    if RESULTS.exists():
        data = json.loads(RESULTS.read_text())
    data["records"] += records
    text = "{\n" + f' "description": {json.dumps(data["description"])},\n "records": [\n'
    text += ",\n".join("  " + json.dumps(r) for r in data["records"]) + "\n ]\n}\n"
    tmp = RESULTS.with_suffix(".json.tmp")
    tmp.write_text(text)
    os.replace(tmp, RESULTS)


if __name__ == "__main__":
    main()
