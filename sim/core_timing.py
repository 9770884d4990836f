#!/usr/bin/env python3
"""The cycle model's shader-core timing against the RTL chip's (docs/chip.md "Calibration").

Runs small loops, each one kind of instruction sequence, as firmware on the rtl and the
cycle backends, at two iteration counts and one, two and a whole chunk's lanes (each
instruction's lanes one a cycle or issue_lanes a cycle), and requires
that an iteration costs the same cycles on both: the per-iteration difference of two
runs cancels the launch and the frame's end, so what is compared is the pipeline
(spec/latencies.toml [latency.<format>] reissue, result, to_unit, from_unit, from_rays,
the sfu's and the traversal unit's latencies, the data cache port). Exit 1 on a
difference, with the loop, the lanes and both costs.

    sim/core_timing.py RPU --config tiny
    sim/core_timing.py RPU --config default --loop store --lanes 128   # every thread of the chip
    sim/core_timing.py RPU --config rpu2005 --lanes 16 --lanes 32     # 4 and 8 chunks of one core
"""
import argparse
import json
import pathlib
import re
import subprocess
import sys
import tempfile

# Registers: r2 = (2, 2, 2, 2), r15.x = the launch block's address (a readable word),
# r12.x = the thread's pixel in the framebuffer (a writable one), r6/r7 = a ray from
# z = -10 straight at the middle of the tetrahedron, r14.x = words in .data 4 KiB apart
# (one cache set in every configuration: five of them miss in four ways).
PROLOGUE = """raygen:
        li      r15.x, DEVICE_LAUNCH_BASE
        li      r14.x, far
        li      r11.x, far
        ld1     r12.x, [r15 + LAUNCH_FRAMEBUFFER_AT]
        rdsr    r13, pixel
        shli    r13.z, r13.z, 4
        iadd    r12.x, r12.x, r13.z
        lif     r2, 2.0
        lif     r6.x, 0.1
        lif     r6.y, 0.05
        lif     r6.z, -10.0
        lif     r6.w, 0.0
        lif     r7.xy, 0.0
        lif     r7.z, 1.0
        lif     r7.w, inf
        li      r3.x, {iterations}
loop:
"""
EPILOGUE = """        iaddi   r3.x, r3.x, -1
        bnz     r3.x, loop
        halt
leaf:   ret
hit_whitted:
        ret
.data
far:    .space  5 * 4096
"""
LOOPS = {
    "independent": ["iaddi r9.x, r2.x, 1", "add r10, r2, r2", "mad r8, r2, r2, r2"],
    "dependent": ["iaddi r4.x, r4.x, 1", "add r5, r4, r2", "dp4 r6.w, r5, r5", "mul r8.x, r6.w, r2.x"],
    "load use": ["ld1 r4.x, [r15 + 0]", "iaddi r5.x, r4.x, 1", "ld r8, [r15 + 4]", "add r9, r8, r2"],
    # Each address waits for the load before (its word is 0): one miss at a time.
    "load miss": [line for k in range(5) for line in
                        (f"ld1 r4.x, [r11 + {4096 * k}]", "iadd r11.x, r14.x, r4.x")],
    "load independent": ["ld1 r4.x, [r15 + 0]", "iaddi r5.x, r2.x, 1"],
    "store": ["st1 [r12 + 4], r2.x", "st [r12], r2", "iaddi r5.x, r2.x, 1"],
    "stack": ["push r2", "push r2.wzyx", "pop r4", "pop r5", "add r8, r4, r5"],
    "call": ["call leaf", "iaddi r5.x, r2.x, 1"],
    "sfu one lane": ["rcp r4.x, r2.x", "add r5.x, r4.x, r2.x"],
    "sfu four lanes": ["rcp r4, r2", "sqrt r5.xy, r2", "add r8, r4, r5"],
    "rsq": ["rsq r4.x, r2.x", "add r5.x, r4.x, r2.x"],
    "trace": ["trace r4, r6, r7", "iaddi r5.x, r4.w, 1"],
    "trace any hit": ["tracea r4, r6, r7", "trace r5, r6, r7", "add r8, r4, r5"],
}


def cycles(rpu, backend, config, firmware, lanes, work):
    stats = work / "stats.json"
    command = [rpu, "render", "tetra:1", "--firmware", firmware, "--backend", backend, "--config", config,
               "--width", str(lanes), "--height", "1", "-o", work / "frame.png", "--stats", stats]
    r = subprocess.run(command, capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"core_timing: {' '.join(map(str, command))} failed ({r.returncode}):\n{r.stderr}")
    return json.loads(stats.read_text())["cycles"]


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("rpu")
    p.add_argument("--config", required=True)
    p.add_argument("--iterations", type=int, nargs=2, default=[8, 24])
    p.add_argument("--loop", action="append", choices=LOOPS, help="these loops only (default: all)")
    p.add_argument("--lanes", type=int, action="append", help="this many threads (the frame's width: more than a "
                   "chunk runs several chunks, cores at once) instead of one, two and a chunk's lanes (repeatable)")
    args = p.parse_args()
    few, many = args.iterations
    shown = subprocess.run([args.rpu, "config", "show", args.config], capture_output=True, text=True, check=True)
    chunk = int(re.search(r"^chunk_size = (\d+)", shown.stdout, re.M).group(1))
    failed = 0
    with tempfile.TemporaryDirectory() as tmp:
        work = pathlib.Path(tmp)
        for name, body in LOOPS.items():
            if args.loop and name not in args.loop:
                continue
            for lanes in args.lanes or sorted({1, 2, chunk}):
                per = {}
                for backend in ("rtl", "cycle"):
                    runs = []
                    for n in (few, many):
                        firmware = work / f"loop{n}.s"
                        firmware.write_text(PROLOGUE.format(iterations=n) +
                                            "".join(f"        {line}\n" for line in body) + EPILOGUE)
                        runs.append(cycles(args.rpu, backend, args.config, firmware, lanes, work))
                    per[backend] = (runs[1] - runs[0]) / (many - few)
                ok = per["rtl"] == per["cycle"]
                failed += not ok
                print(f"{'ok  ' if ok else 'FAIL'} {args.config}: {name}, {lanes} lane{'s' if lanes > 1 else ''}: "
                      f"{per['rtl']:g} cycles an iteration on the rtl backend, {per['cycle']:g} on the cycle backend")
    if failed:
        print(f"core_timing: {failed} loops cost differently on the cycle backend; spec/latencies.toml "
              "[latency.<format>] and docs/cycle-model.md \"Shader cores\" describe its timing")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
