#!/usr/bin/env python3
"""The stats a run writes say how the run was made (docs/cycle-model.md, "Statistics").

    stats_facts.py RPU OUT_DIR

Renders balls:2 on the cycle backend with a configuration written from scratch
(tests/cli/configs/from_scratch.toml) and a --set on top, then checks that the JSON
holds every fact of the run and the whole resolved configuration, and that the CSV is
one wide row whose columns are the JSON's values.
"""
import csv
import json
import pathlib
import shlex
import subprocess
import sys

rpu, out = sys.argv[1], pathlib.Path(sys.argv[2])
out.mkdir(parents=True, exist_ok=True)
json_path, csv_path = out / "facts.json", out / "facts.csv"
command = [rpu, "render", "balls:2", "--backend", "cycle", "--config", "tests/cli/configs/from_scratch.toml",
           "--set", "data_cache.bytes=4096", "--width", "24", "--height", "16", "--spp", "2", "--seed", "7",
           "--isect", "watertight", "--stats", str(json_path), str(csv_path), "-o", str(out / "facts.png")]
r = subprocess.run(command, capture_output=True, text=True)
failures = []


def check(ok, what):
    if not ok:
        failures.append(what)


check(r.returncode == 0, f"exit {r.returncode}: {r.stderr}")
if r.returncode == 0:
    stats = json.loads(json_path.read_text())
    run = stats.get("run", {})
    check(run.get("command_line") == shlex.join(command), f"run.command_line {run.get('command_line')}")
    check(run.get("scene") == "balls:2", f"run.scene {run.get('scene')}")
    check((run.get("width"), run.get("height")) == (24, 16), "run.width/height")
    check(run.get("spp") == 2, "run.spp")
    check(run.get("seed") == 7, "run.seed")
    check(run.get("format") == "E7M16", f"run.format {run.get('format')}")
    check(run.get("isect") == "watertight", "run.isect")
    check(run.get("backend") == "cycle", "run.backend")
    check(isinstance(run.get("version"), str) and run["version"], "run.version")
    commit = run.get("commit", "")
    check(commit == "unknown" or len(commit.removesuffix("-dirty")) == 40, f"run.commit {commit}")
    check(isinstance(run.get("host_seconds"), (int, float)) and run["host_seconds"] > 0, "run.host_seconds")
    check(isinstance(run.get("host_threads"), int) and run["host_threads"] >= 1, "run.host_threads")
    config = stats.get("config", {})
    check(config.get("name") == "two_core", f"config.name {config.get('name')}")
    check(config.get("data_cache", {}).get("bytes") == 4096, "config.data_cache.bytes is the --set's 4096")
    check(config.get("stack_depth") == 24, "config.stack_depth from the file")
    check(config.get("data_cache", {}).get("sets") == 4096 // (32 * 2), "config.data_cache.sets derived")
    check(config.get("tu", {}).get("setup_watertight") == 133, "config.tu latencies of rpu24")
    show = subprocess.run([rpu, "config", "show", "tests/cli/configs/from_scratch.toml", "--set",
                           "data_cache.bytes=4096"], capture_output=True, text=True).stdout
    for line in show.splitlines():
        # Every choice `rpu config show` prints is in the stats.
        if "=" in line and not line.startswith("#"):
            key = line.split("=")[0].strip()
            check(key in config or any(key in v for v in config.values() if isinstance(v, dict)),
                  f"config lacks '{key}'")
    cycles = stats["cycles"]
    rays = stats["rays"]["closest"] + stats["rays"]["any"]
    rates = stats.get("rates", {})
    check(abs(rates.get("rays_per_cycle", -1) - rays / cycles) < 1e-9 * max(1, rays / cycles), "rates.rays_per_cycle")
    check(abs(rates.get("rays_per_second", -1) - rays / cycles * 200e6) < 1e-6 * rays / cycles * 200e6,
          "rates.rays_per_second at 200 MHz")
    rows = list(csv.reader(csv_path.open()))
    check(len(rows) == 2, f"the CSV has {len(rows)} rows, expected a header and one run")
    if len(rows) == 2:
        header, row = rows
        check(len(header) == len(row), "the CSV's row has a value per column")
        values = dict(zip(header, row))
        check(values.get("config.data_cache.bytes") == "4096", "CSV config.data_cache.bytes")
        check(values.get("cycles") == str(cycles), "CSV cycles")
        check(values.get("run.scene") == "balls:2", "CSV run.scene")
for f in failures:
    print(f"FAIL {f}")
print("ok" if not failures else f"{len(failures)} failures")
sys.exit(1 if failures else 0)
