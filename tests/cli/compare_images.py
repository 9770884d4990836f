#!/usr/bin/env python3
"""rpu render --compare measures an image against another (docs/accuracy.md, "Measuring").

    compare_images.py RPU OUT_DIR

Renders tetra:1 with the reference backend to an EXR, then with the functional backend
against it (PSNR, max error and dark dots printed and in --stats), then the reference again against
itself and the functional image against its own EXR (identical: infinite PSNR, null in
the stats, error 0), and checks the refusals: a PNG, another size.
"""
import csv
import json
import pathlib
import re
import subprocess
import sys

rpu, out = sys.argv[1], pathlib.Path(sys.argv[2])
out.mkdir(parents=True, exist_ok=True)
size = ["--width", "16", "--height", "12", "--spp", "1"]
failures = []


def check(ok, what):
    if not ok:
        failures.append(what)


def run(*args):
    return subprocess.run([rpu, "render", "tetra:1", *size, *args], capture_output=True, text=True)


reference = out / "reference.exr"
r = run("-o", str(reference), str(out / "reference.png"))
check(r.returncode == 0, f"reference render: exit {r.returncode}: {r.stderr}")

r = run("--backend", "functional", "--compare", str(reference), "--stats", str(out / "functional.json"),
        str(out / "functional.csv"), "-o", str(out / "functional.png"))
check(r.returncode == 0, f"functional --compare: exit {r.returncode}: {r.stderr}")
m = re.search(r"against .*reference.exr: PSNR ([0-9.]+) dB, max error ([0-9.e+-]+), ([0-9]+) dark dots "
              r"\(([0-9.]+)% of the image\)", r.stderr)
check(m is not None, f"no comparison printed: {r.stderr}")
if r.returncode == 0 and m:
    stats = json.loads((out / "functional.json").read_text())
    compare = stats.get("compare", {})
    check(compare.get("image") == str(reference), f"compare.image {compare.get('image')}")
    check(abs(compare.get("psnr_db", -1) - float(m.group(1))) < 0.01, f"compare.psnr_db {compare.get('psnr_db')}")
    check(20 < compare.get("psnr_db", 0) < 200, f"fp32 against double: PSNR {compare.get('psnr_db')}")
    check(0 < compare.get("max_error", 0) < 0.1, f"compare.max_error {compare.get('max_error')}")
    check(compare.get("dark_dots") == int(m.group(3)), f"compare.dark_dots {compare.get('dark_dots')}")
    check(abs(float(m.group(4)) - 100 * int(m.group(3)) / (16 * 12)) < 0.001, f"dark dots' share {m.group(4)}%")
    with open(out / "functional.csv", newline="") as f:
        header, row = list(csv.reader(f))
    check(all(f"compare.{k}" in header for k in ("psnr_db", "max_error", "dark_dots")), f"CSV header {header}")

r = run("--compare", str(reference), "-o", str(out / "again.png"))
check(r.returncode == 0 and "PSNR inf dB, max error 0, 0 dark dots" in r.stderr,
      f"the reference against itself: {r.stderr}")
r = run("--backend", "functional", "-o", str(out / "functional.exr"))
check(r.returncode == 0, f"functional EXR: {r.stderr}")
same = out / "same.json"
r = run("--backend", "functional", "--compare", str(out / "functional.exr"), "--stats", str(same), "-o",
        str(out / "same.png"))
check(r.returncode == 0 and same.exists() and json.loads(same.read_text())["compare"]["psnr_db"] is None,
      f"identical images: psnr_db is null: {r.stderr}")

r = run("--compare", str(out / "reference.png"), "-o", str(out / "never.png"))
check(r.returncode == 1 and "--compare" in r.stderr and "give a linear .exr" in r.stderr, f"a PNG: {r.stderr}")
r = subprocess.run([rpu, "render", "tetra:1", "--width", "8", "--height", "8", "--compare", str(reference), "-o",
                    str(out / "never.png")], capture_output=True, text=True)
check(r.returncode == 1 and "the image is 16x12 pixels, the render 8x8" in r.stderr, f"another size: {r.stderr}")
r = run("--compare", str(reference), "-o", str(reference))
check(r.returncode == 1 and "reference.exr" in r.stderr, f"overwriting the compared image: {r.stderr}")

for f in failures:
    print("FAIL:", f)
sys.exit(1 if failures else 0)
