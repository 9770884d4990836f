#!/usr/bin/env python3
"""Lint, synthesis and netlist simulation of the RTL units (docs/rtl.md).

Formats and units come from spec/formats.toml and spec/fp_units.toml, the same tables
gen.py turns into rpu_pkg.sv, so nothing here repeats a width or a unit list.

    flow.py lint  --verilator verilator --pkg build/ci/generated/rtl/rpu_pkg.sv
    flow.py synth --unit fma --format fp16 --pkg ... --cosim build/ci/sim/fp_cosim --out DIR
    flow.py synth --unit iu --isect woop --format fp16 --pkg ... --cosim build/ci/sim/iu_cosim --out DIR
    flow.py synth --unit tu --isect woop --format fp16 [--slots 4] --pkg ... --cosim build/ci/sim/tu_cosim --out DIR
    flow.py synth --unit mem --config tiny --pkg ... --cosim build/ci/sim/mem_cosim --out DIR
    flow.py synth --unit chip --config tiny --netlist --pkg ... --cosim build/release/sim/chip_cosim --out DIR
    flow.py area  --from DIR --commit HASH    # appends to bench/results/area.json
"""
from __future__ import annotations

import argparse
import json
import os
import pathlib
import re
import shutil
import subprocess
import sys
import tempfile
import time

ROOT = pathlib.Path(__file__).resolve().parent.parent
RTL = ROOT / "rtl"
# The FP units' and the IU's netlists: one request and one response stream in order.
STREAM_NETLIST_TB = ROOT / "sim" / "rpu_stream_netlist_tb.sv"
TU_NETLIST_TB = ROOT / "sim" / "rpu_tu_netlist_tb.sv"
MEM_NETLIST_TB = ROOT / "sim" / "rpu_mem_netlist_tb.sv"
CHIP_NETLIST_TB = ROOT / "sim" / "rpu_chip_netlist_tb.sv"
# The memory system the mem harness's top wraps.
MEM_SYSTEM = ROOT / "sim" / "rpu_mem_system.sv"
# The intersection modes (spec/memory_map.toml [isect_mode]: the IsectMode parameter).
ISECT_MODES = ("woop", "watertight")


sys.path.insert(0, str(ROOT / "spec"))
import gen  # noqa: E402  (spec/gen.py: loads and validates the tables)
import estimate  # noqa: E402  (rtl/estimate.py, beside this file)


def cache_parameters() -> list[str]:
    """The caches' build-time parameters in gen.RTL_PARAMETERS (NodeBytes, ...)."""
    return [u + p for u, _ in gen.RTL_CACHES for p, _ in gen.RTL_CACHE_PARAMETERS]


def spec() -> tuple[dict, list[dict]]:
    tables = gen.load(ROOT / "spec")
    formats = {x["name"]: x for x in tables["formats"]["format"]}
    return formats, tables["fp_units"]["unit"]


def stream_layouts() -> dict[str, dict]:
    """Each stream's layout (spec/streams.toml): its bits and its fields' low bits."""
    tables = gen.load(ROOT / "spec")
    return {s["name"]: s for s in gen.streams.layout(tables, gen.fp_op_bits(tables))["streams"]}


def stream_bits() -> dict[str, int]:
    """Each stream's width, for the netlist testbenches' ports."""
    return {name: s["bits"] for name, s in stream_layouts().items()}


def stream_field(layout: dict, name: str) -> dict:
    """A field of a stream's layout: its width and low bit."""
    return next(f for f in layout["fields"] if f["name"] == name)


def rtl_sources() -> list[pathlib.Path]:
    return sorted(RTL.glob("*.sv"))


_harness_dir: tempfile.TemporaryDirectory | None = None


def harness_top(name: str) -> pathlib.Path:
    """The co-simulation top of harness `name` (spec/harnesses.toml), generated once per
    run as the build generates it."""
    global _harness_dir
    if _harness_dir is None:
        _harness_dir = tempfile.TemporaryDirectory(prefix="rpu-harness-")
        tables = gen.load(ROOT / "spec")
        hs = gen.harnesses.load(tables, gen.fp_op_bits(tables), gen.harness_sources(ROOT / "spec"))
        gen.harnesses.write_all(hs, pathlib.Path(_harness_dir.name), gen.BANNER, gen.write_if_changed)
    return pathlib.Path(_harness_dir.name) / "sim" / f"rpu_{name}_cosim_top.sv"


def isect_mode(name: str) -> int:
    return gen.load(ROOT / "spec")["memory_map"]["isect_mode"][name]


def run(cmd: list, **kw) -> subprocess.CompletedProcess:
    return subprocess.run([str(c) for c in cmd], capture_output=True, text=True, **kw)


def lint(args) -> int:
    """verilator --lint-only -Wall on every unit in every format (or in --formats), on the
    sim tops, and on every configuration's chip (or --chips': a chip of 8 cores takes 40 s)."""
    formats, units = spec()
    if args.formats:
        unknown = set(args.formats) - set(formats)
        if unknown:
            print(f"flow.py lint: no format {', '.join(sorted(unknown))} in spec/formats.toml", file=sys.stderr)
            return 2
        formats = {name: f for name, f in formats.items() if name in args.formats}
    failures = 0
    jobs = []
    for unit in units:
        for name, f in formats.items():
            jobs.append((f"rpu_fp_{unit['name']} {name}", [f"rpu_fp_{unit['name']}"],
                         [f"-GExpBits={f['exponent_bits']}", f"-GFracBits={f['fraction_bits']}"], []))
    for i, unit in enumerate(units):
        jobs.append((f"rpu_fp_unit_cosim_top {unit['name']}", ["rpu_fp_unit_cosim_top"], [f"-GUnit={i}"],
                     [harness_top("fp_unit")]))
    for isect in ISECT_MODES:
        mode = isect_mode(isect)
        for name, f in formats.items():
            jobs.append((f"rpu_iu {isect} {name}", ["rpu_iu"],
                         [f"-GExpBits={f['exponent_bits']}", f"-GFracBits={f['fraction_bits']}",
                          f"-GIsectMode={mode}"], []))
        jobs.append((f"rpu_iu_cosim_top {isect}", ["rpu_iu_cosim_top"], [f"-GIsectMode={mode}"], [harness_top("iu")]))
    # The traversal unit in every format and both intersection modes, its sim top, and
    # the shared stream primitives.
    for name, f in formats.items():
        for isect in ISECT_MODES:
            jobs.append((f"rpu_tu {name} {isect}", ["rpu_tu"],
                         [f"-GExpBits={f['exponent_bits']}", f"-GFracBits={f['fraction_bits']}",
                          f"-GIsectMode={isect_mode(isect)}"], []))
    # The TU whose ray slots share a node-step pipeline (its set-up engines are rpu_tu
    # with HandOff), every format and mode.
    for name, f in formats.items():
        for isect in ISECT_MODES:
            for packet in (1, 2, 4):
                jobs.append((f"rpu_tu_pipe {name} {isect} Packet={packet}", ["rpu_tu_pipe"],
                             [f"-GExpBits={f['exponent_bits']}", f"-GFracBits={f['fraction_bits']}",
                              f"-GIsectMode={isect_mode(isect)}", "-GSlots=4", "-GSetups=3",
                              f"-GPacket={packet}"], []))
    # The ray unit (TU + IU) in every format and mode; the sim top with and without the IU.
    for name, f in formats.items():
        for isect in ISECT_MODES:
            for pipe in (["-GTuPipe=0"], ["-GTuPipe=1", "-GTuSlots=4"]):
                jobs.append((f"rpu_ray_unit {name} {isect} {' '.join(pipe)}", ["rpu_ray_unit"],
                             [f"-GExpBits={f['exponent_bits']}", f"-GFracBits={f['fraction_bits']}",
                              f"-GIsectMode={isect_mode(isect)}", *pipe], []))
    for with_iu in (0, 1):
        jobs.append((f"rpu_tu_cosim_top WithIu={with_iu}", ["rpu_tu_cosim_top"], [f"-GWithIu={with_iu}"],
                     [harness_top("tu")]))
    for with_iu in (0, 1):
        jobs.append((f"rpu_tu_cosim_top WithIu={with_iu} Pipe=1", ["rpu_tu_cosim_top"],
                     [f"-GWithIu={with_iu}", "-GPipe=1", "-GSlots=16"], [harness_top("tu")]))
    for top in ("rpu_fifo", "rpu_skid_buf"):
        jobs.append((top, [top], ["-GWidth=8"], []))
    # The shader core as each named configuration builds it (its build-time parameters
    # from spec/configs.toml), a core of 1-thread chunks, and its co-simulation top.
    tables = gen.load(ROOT / "spec")
    if args.chips:
        unknown = set(args.chips) - {r["name"] for r in tables["resolved"]}
        if unknown:
            print(f"flow.py lint: no configuration {', '.join(sorted(unknown))} in spec/configs.toml",
                  file=sys.stderr)
            return 2
    for r in tables["resolved"]:
        params = gen.rtl_parameters(tables, r["values"])
        spu = {k: v for k, v in params.items()
               if k not in ("StackDepth", "RayUnits", "RayCaches", "TuSlots", "TuPipe", "TuSetups", "TuByTag", "TuPacket")
               and k not in cache_parameters()}
        jobs.append((f"rpu_spu {r['name']}", ["rpu_spu"], [f"-G{k}={v}" for k, v in spu.items()], []))
        if args.chips and r["name"] not in args.chips:
            continue
        # The chip takes every parameter of the configuration.
        jobs.append((f"rpu_top {r['name']}", ["rpu_top"], [f"-G{k}={v}" for k, v in params.items()], []))
        # A pipelined unit's memory answers either way (tu_by_tag): lint the other too.
        if params["TuPipe"]:
            other = {**params, "TuByTag": 1 - params["TuByTag"]}
            jobs.append((f"rpu_top {r['name']} TuByTag={other['TuByTag']}", ["rpu_top"],
                         [f"-G{k}={v}" for k, v in other.items()], []))
    jobs.append(("rpu_spu chunks of 1", ["rpu_spu"], ["-GThreads=4", "-GChunkSize=1", "-GSfuUnits=4"], []))
    for lanes in (2, 4):
        jobs.append((f"rpu_spu issue lanes {lanes}", ["rpu_spu"],
                     ["-GThreads=16", "-GChunkSize=4", f"-GIssueLanes={lanes}"], []))
    jobs.append(("rpu_spu_cosim_top", ["rpu_spu_cosim_top"], [], [harness_top("spu")]))
    # The memory system: each named configuration's three caches, the co-simulation
    # top of each configuration's memory system and with its defaults (the corner
    # cases mem_cosim also runs), the arbiters at 1 to 6 ports and the in-order port
    # at several tag widths.
    for r in tables["resolved"]:
        params = gen.rtl_parameters(tables, r["values"])
        for unit, _ in gen.RTL_CACHES:
            cache = [f"-G{p}={params[unit + p]}" for p, _ in gen.RTL_CACHE_PARAMETERS]
            jobs.append((f"rpu_cache {r['name']} {unit.lower()}", ["rpu_cache"], cache, []))
        top = [f"-G{k}={v}" for k, v in params.items() if k in cache_parameters()]
        jobs.append((f"rpu_mem_cosim_top {r['name']}", ["rpu_mem_cosim_top"], top, [MEM_SYSTEM, harness_top("mem")]))
    jobs.append(("rpu_mem_cosim_top corners (its defaults)", ["rpu_mem_cosim_top"], [],
                 [MEM_SYSTEM, harness_top("mem")]))
    for n in (1, 2, 3, 6):
        jobs.append((f"rpu_cache_arbiter {n}", ["rpu_cache_arbiter"], [f"-GRequesters={n}"], []))
        jobs.append((f"rpu_mem_arbiter {n}", ["rpu_mem_arbiter"], [f"-GCaches={n}"], []))
    for bits in (1, 2, 4):
        jobs.append((f"rpu_inorder_port TagBits={bits}", ["rpu_inorder_port"], [f"-GTagBits={bits}"], []))
    for what, (top,), params, extra in jobs:
        r = run([args.verilator, "--lint-only", "-Wall", RTL / "lint.vlt", args.pkg, *rtl_sources(), *extra,
                 "--top-module", top, *params])
        ok = r.returncode == 0 and "%Warning" not in r.stderr
        print(f"{'ok  ' if ok else 'FAIL'} lint {what}")
        if not ok:
            print(r.stdout + r.stderr)
            failures += 1
    return 1 if failures else 0


# synth's fine stage with memory_map on the memories read in the same cycle alone (the
# caches' tags and LRU order: register files, flops and multiplexers): each rpu_ram,
# read the cycle after, stays one $mem cell (a RAM macro or block RAM, counted in bits
# apart from the logic).
KEEP_RAMS = ["memory_map r:RD_CLK_ENABLE=1'b0", "opt -fast -full", "opt -full", "techmap", "opt -fast",
             "abc -fast", "opt -fast"]


def yosys(args, top: str, chparams: dict, extra: list, out: pathlib.Path, stem: str,
          keep_rams: bool = False) -> dict | None:
    """Synthesises `top` with the parameters; returns the stat numbers, or None on failure.
    With keep_rams the RAMs stay memories, and the stats hold their bits (ram_bits)."""
    netlist = out / f"{stem}.v"
    log = out / f"{stem}.yosys.log"
    reads = " ".join(str(p) for p in [args.pkg, *rtl_sources(), *extra])
    synth_steps = [f"synth -flatten -top {top} -run begin:fine", *KEEP_RAMS] if keep_rams else \
        [f"synth -flatten -top {top}"]
    script = "; ".join([
        f"read_verilog -sv {reads}",
        f"hierarchy -check -top {top} " + " ".join(f"-chparam {k} {v}" for k, v in chparams.items()),
        *synth_steps,
        "splitnets",
        "stat",
        "stat -tech cmos",
        f"write_verilog -noattr {netlist}",
    ])
    start = time.monotonic()
    text = run_yosys(args, script, log)
    if text is None:
        return None
    stats = parse_stat(text)
    stats.update(synth_seconds=round(time.monotonic() - start, 1))
    if keep_rams:
        # Each memory as write_verilog declares it: reg [W-1:0] name [D-1:0].
        rams = re.findall(r"^\s*reg \[(\d+):0\] \S+\s+\[(\d+):0\];", netlist.read_text(), re.M)
        stats.update(rams=len(rams), ram_bits=sum((int(w) + 1) * (int(d) + 1) for w, d in rams))
    print(f"ok   yosys {stem}: {stats['cells']} cells in {stats['synth_seconds']:.1f} s")
    return stats


def run_yosys(args, script: str, log: pathlib.Path) -> str | None:
    """Runs the Yosys script, its output to `log`; returns the output, or None (with the
    reason printed) if Yosys failed or warned."""
    # Yosys writes the log as it goes: a long synthesis shows where it is.
    r = run([args.yosys, "-l", log, "-p", script])
    if r.stderr:
        with log.open("a") as f:
            f.write(r.stderr)
    if r.returncode != 0:
        print(f"synth FAIL: yosys exited {r.returncode}; log in {log}\n{r.stderr[-3000:]}")
        return None
    # Yosys 0.23 reports some mis-read constructs only as warnings (arrays of packed
    # structs become 1-bit flops, docs/style.md "What Yosys 0.23 reads"), so any warning fails the run.
    warnings = [l for l in r.stdout.splitlines() if l.startswith("Warning:")]
    if warnings:
        print("synth FAIL: yosys warnings:\n" + "\n".join(warnings))
        return None
    return r.stdout


def synth(args) -> int:
    """Yosys synth of one unit and format, then the netlist against the model's vectors."""
    formats, units = spec()
    if args.unit == "mem":
        return synth_mem(args)
    if args.unit in ("chip", "core"):
        return synth_chip(args)
    if args.format is None:
        print("flow.py: --format is required for this unit", file=sys.stderr)
        return 2
    if args.unit in RAY_UNIT_SYNTH:
        return synth_ray_unit(args, formats)
    names = [u["name"] for u in units]
    if args.unit not in names or args.format not in formats:
        print(f"flow.py: unknown unit or format; units {names + ['iu', 'tu']}, formats {list(formats)}",
              file=sys.stderr)
        return 2
    f = formats[args.format]
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    stem = f"{args.unit}_{args.format}"
    netlist = out / f"{stem}.v"
    stats = yosys(args, "rpu_fp_unit_cosim_top", {"Unit": names.index(args.unit), "ExpBits": f["exponent_bits"],
                                             "FracBits": f["fraction_bits"]}, [harness_top("fp_unit")], out, stem)
    if stats is None:
        return 1
    stats.update(unit=args.unit, format=args.format, exponent_bits=f["exponent_bits"],
                 fraction_bits=f["fraction_bits"])

    # Every op of the unit through the netlist, with vectors from the C++ model.
    start = time.monotonic()
    bits = stream_bits()
    simulate = build_netlist_sim(args, out, stem, netlist, STREAM_NETLIST_TB, "rpu_stream_netlist_tb",
                                 {"ReqBits": bits["fp_req"], "RspBits": bits["fp_rsp"]},
                                 {"RPU_STREAM_DUT": "rpu_fp_unit_cosim_top"})
    if simulate is None:
        return 1
    stats.update(netlist_build_seconds=round(time.monotonic() - start, 1))
    # args.vectors random vectors in all, shared evenly by the unit's ops, plus an even
    # sample of each op's edge and constructed vectors (a quarter as many).
    unit = next(u for u in units if u["name"] == args.unit)
    per_op = -(-args.vectors // len(unit["ops"]))
    total = 0
    start = time.monotonic()
    for op in unit["ops"]:
        vectors = out / f"{stem}_{op}.vec"
        r = run([args.cosim, "--format", args.format, "--op", op, "--count", per_op,
                 "--edge-limit", max(1, per_op // 4), "--write-vectors", vectors])
        if r.returncode != 0:
            print(f"synth FAIL: {args.cosim} --write-vectors:\n{r.stdout}{r.stderr}")
            return 1
        r = run([*simulate, f"+vectors={vectors}"])
        text = r.stdout + r.stderr
        if r.returncode != 0 or "netlist ok" not in text:
            print(f"synth FAIL: netlist of {args.unit} in {args.format}, op {op}:\n{text}")
            return 1
        n = int(re.search(r"netlist ok: (\d+) vectors", text).group(1))
        total += n
        print(f"ok   netlist {args.unit} {args.format} {op}: {n} vectors")
        vectors.unlink()
    stats.update(netlist_vectors=total, netlist_seconds=round(time.monotonic() - start, 1),
                 netlist_simulator=args.sim)
    (out / f"{stem}.json").write_text(json.dumps(stats, indent=1) + "\n")
    print(f"synth ok: {args.unit} {args.format}: {stats['cells']} cells ({stats['flops']} flops), "
          f"{stats.get('transistors', '?')} CMOS transistors; {total} netlist vectors match")
    return 0


# The intersection and traversal units' syntheses: the sim top Yosys reads, the netlist
# testbench, the harness' arguments that write its vectors (iu_cosim: IU tests captured
# from Cornell box rays; tu_cosim: a third each camera, random and shadow rays with the
# memory image and the Tracer's IU tests in walk order), the testbench's last line and
# its stream-width parameters; and the design, which docs/area.md shows beside the unit
# (bench/results/area.json keeps the records of earlier designs).
RAY_UNIT_SYNTH = {
    "iu": {"top": "rpu_iu_cosim_top", "harness": "iu", "design": "pipeline, one test a cycle",
           "tb": STREAM_NETLIST_TB, "tb_top": "rpu_stream_netlist_tb",
           "defines": {"RPU_STREAM_DUT": "rpu_iu_cosim_top"},
           "vector_args": lambda n: ["--rays", 100000, "--vectors", n],
           "done": r"netlist ok: (\d+) vectors",
           "streams": {"ReqBits": "iu_req", "RspBits": "iu_rsp"}},
    "tu": {"top": "rpu_tu_cosim_top", "harness": "tu", "tb": TU_NETLIST_TB, "tb_top": "rpu_tu_netlist_tb",
           "vector_args": lambda n: ["--rays", -(-n // 3)],
           "done": r"netlist ok: (\d+) rays \(\d+ IU tests\)",
           "streams": {"CfgBits": "tu_cfg", "ReqBits": "tu_req", "RspBits": "tu_rsp", "MemReqBits": "mem_req",
                       "MemRspBits": "mem_rsp", "IuReqBits": "iu_req", "IuRspBits": "iu_rsp"}},
}


def synth_ray_unit(args, formats: dict) -> int:
    """Yosys synth of the intersection or traversal unit in one mode and format; the
    netlist then runs the vectors its co-simulation harness wrote (RAY_UNIT_SYNTH)."""
    if args.isect not in ISECT_MODES or args.format not in formats:
        print(f"flow.py: unknown mode or format; modes {ISECT_MODES}, formats {list(formats)}", file=sys.stderr)
        return 2
    kind = RAY_UNIT_SYNTH[args.unit]
    f = formats[args.format]
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    if args.slots < 1 or (args.slots > 1 and args.unit != "tu"):
        print("flow.py: --slots is a traversal unit's ray slots (1 or more)", file=sys.stderr)
        return 2
    if args.pipe and (args.unit != "tu" or args.slots < 2):
        print("flow.py: --pipe is a traversal unit's with 2 or more --slots", file=sys.stderr)
        return 2
    if args.packet != 1 and not args.pipe:
        print("flow.py: --packet is a pipelined traversal unit's (--pipe)", file=sys.stderr)
        return 2
    unit = f"{args.unit}_{args.isect}"
    stem = f"{unit}_{args.format}" + (f"_s{args.slots}" if args.slots > 1 else "") + \
        (f"_pipe_e{args.setups}" if args.pipe else "") + (f"_p{args.packet}" if args.packet != 1 else "")
    netlist = out / f"{stem}.v"
    params = {"ExpBits": f["exponent_bits"], "FracBits": f["fraction_bits"], "IsectMode": isect_mode(args.isect)}
    if args.unit == "tu":
        params["Slots"] = args.slots
    if args.pipe:
        params.update(Pipe=1, Setups=args.setups, Packet=args.packet)
    # The pipeline's stacks are one RAM: kept as a memory, its bits counted apart.
    stats = yosys(args, kind["top"], params, [harness_top(kind["harness"])], out, stem, keep_rams=args.pipe)
    if stats is None:
        return 1
    stats.update(unit=unit, format=args.format, exponent_bits=f["exponent_bits"], fraction_bits=f["fraction_bits"])
    if args.unit == "tu":
        stats["slots"] = args.slots
    if "design" in kind:
        stats["design"] = kind["design"]
    if args.slots > 1:
        stats["design"] = f"{args.slots} ray slots, a walker each"
    if args.pipe:
        stats["design"] = f"{args.slots} ray slots sharing a node-step pipeline, {args.setups} set-up engines"
    if args.packet != 1:
        stats["design"] = (f"{args.slots} slots of packets of {args.packet} rays sharing a node-step pipeline, "
                           f"{args.setups} set-up engines")
        stats["packet"] = args.packet
    if args.pipe:
        stats["setups"] = args.setups
    if not args.cosim:
        # Synthesis only (an area for an estimate): no netlist to compare.
        (out / f"{stem}.json").write_text(json.dumps(stats, indent=1) + "\n")
        print(f"synth ok: {unit} {args.format}: {stats['cells']} cells ({stats['flops']} flops), "
              f"{stats.get('transistors', '?')} CMOS transistors; the netlist not simulated (no --cosim)")
        return 0
    start = time.monotonic()
    layouts = stream_layouts()
    tb_params = {param: layouts[stream]["bits"] for param, stream in kind["streams"].items()}
    if args.unit == "tu":
        # The tags, by which the testbench matches responses and (with slots) IU tests.
        tags = {stream: stream_field(layouts[stream], "tag") for stream in ("tu_rsp", "iu_req", "iu_rsp")}
        tb_params.update(TagBits=tags["tu_rsp"]["width"], RspTagLsb=tags["tu_rsp"]["lsb"],
                         IuReqTagLsb=tags["iu_req"]["lsb"], IuRspTagLsb=tags["iu_rsp"]["lsb"], Slots=args.slots)
        if args.pipe:
            # The testbench keeps the slots, the set-up engines and their buffers busy and
            # finds each test's ray by its fields (t_best is the unit's of the time).
            tb_params.update(Pipe=1, Slots=args.slots + 2 * args.setups + 2,
                             IuReqTBestLsb=stream_field(layouts["iu_req"], "t_best")["lsb"])
    simulate = build_netlist_sim(args, out, stem, netlist, kind["tb"], kind["tb_top"], tb_params,
                                 kind.get("defines"))
    if simulate is None:
        return 1
    stats.update(netlist_build_seconds=round(time.monotonic() - start, 1))
    vectors = out / f"{stem}.vec"
    # tu_cosim's shadow rays start at camera hits: where few camera rays hit (fp16's
    # watertight products overflow at the Cornell box's coordinates), ask for more rays
    # until the file holds args.vectors.
    want = args.vectors
    for _ in range(4):
        r = run([args.cosim, "--format", args.format, "--isect", args.isect, "--scene", "cornell",
                 *kind["vector_args"](want), *(["--pipe", "--packet", args.packet] if args.packet != 1 else []),
                 "--write-vectors", vectors])
        if r.returncode != 0:
            print(f"synth FAIL: {args.cosim} --write-vectors:\n{r.stdout}{r.stderr}")
            return 1
        m = re.search(r"wrote (\d+) (rays|IU tests)", r.stdout)
        written = int(m.group(1)) if m else args.vectors
        if written >= args.vectors:
            break
        want = want * args.vectors // written + 1
    start = time.monotonic()
    r = run([*simulate, f"+vectors={vectors}"])
    text = r.stdout + r.stderr
    m = re.search(kind["done"], text)
    if r.returncode != 0 or not m:
        print(f"synth FAIL: netlist of {unit} in {args.format}:\n{text}")
        return 1
    total = int(m.group(1))
    vectors.unlink()
    stats.update(netlist_vectors=total, netlist_seconds=round(time.monotonic() - start, 1),
                 netlist_simulator=args.sim)
    (out / f"{stem}.json").write_text(json.dumps(stats, indent=1) + "\n")
    print(f"synth ok: {unit} {args.format}: {stats['cells']} cells ({stats['flops']} flops), "
          f"{stats.get('transistors', '?')} CMOS transistors; {m.group(0).removeprefix('netlist ok: ')} "
          f"through the netlist match the C++ model")
    return 0


def synth_mem(args) -> int:
    """Yosys synth of a named configuration's data cache alone (cells, flops, RAM bits),
    then of its whole memory system (rpu_mem_cosim_top: three caches with their arbiters
    and in-order ports, the memory arbiter), whose netlist replays every cycle of a
    mem_cosim run on that configuration and must match the RTL's outputs in every bit."""
    tables = gen.load(ROOT / "spec")
    resolved = {r["name"]: r for r in tables["resolved"]}
    if args.config not in resolved:
        print(f"flow.py: unknown configuration '{args.config}'; spec/configs.toml has {list(resolved)}",
              file=sys.stderr)
        return 2
    params = gen.rtl_parameters(tables, resolved[args.config]["values"])
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    stem = f"mem_{args.config}"
    data_cache = {p: params["Data" + p] for p, _ in gen.RTL_CACHE_PARAMETERS}
    cache = yosys(args, "rpu_cache", {**data_cache, "CacheId": 2}, [], out, f"{stem}_data_cache", keep_rams=True)
    system = yosys(args, "rpu_mem_cosim_top", {k: params[k] for k in cache_parameters()},
                   [MEM_SYSTEM, harness_top("mem")], out, stem,
                   keep_rams=True)
    if cache is None or system is None:
        return 1
    netlist = out / f"{stem}.v"
    # The testbench's port widths from the netlist itself (how many ports of each kind
    # the top has) and the spec (each stream's bits).
    widths = {m.group(2): int(m.group(1)) + 1 if m.group(1) else 1
              for m in re.finditer(r"^\s*(?:input|output)\s+(?:\[(\d+):0\]\s+)?(\w+);", netlist.read_text(), re.M)}
    bits = stream_bits()
    tb_params = {"Raw": widths["req_valid_i"], "InOrder": widths["mem_req_valid_i"], "Caches": widths["idle_o"],
                 "ReqBits": bits["cache_req"], "RspBits": bits["cache_rsp"], "MemReqBits": bits["mem_req"],
                 "MemRspBits": bits["mem_rsp"], "DramReqBits": bits["dram_req"], "DramRspBits": bits["dram_rsp"],
                 "CounterBits": bits["cache_counters"], "GeometryBits": bits["cache_geometry"]}
    start = time.monotonic()
    simulate = build_netlist_sim(args, out, stem, netlist, MEM_NETLIST_TB, "rpu_mem_netlist_tb", tb_params)
    if simulate is None:
        return 1
    build_seconds = time.monotonic() - start
    vectors = out / f"{stem}.vec"
    r = run([args.cosim, "--model", args.config, "--cache", "all", "--requests", args.vectors, "--coverage",
             "--write-vectors", vectors])
    if r.returncode != 0:
        print(f"synth FAIL: {args.cosim} --write-vectors:\n{r.stdout}{r.stderr}")
        return 1
    start = time.monotonic()
    r = run([*simulate, f"+vectors={vectors}"])
    text = r.stdout + r.stderr
    m = re.search(r"netlist ok: (\d+) cycles", text)
    if r.returncode != 0 or not m:
        print(f"synth FAIL: netlist of the {args.config} memory system:\n{text[-5000:]}")
        return 1
    vectors.unlink()
    result = {"unit": "mem", "config": args.config, "data_cache": cache, "memory_system": system,
              "netlist_cycles": int(m.group(1)), "netlist_requests_per_cache": args.vectors,
              "netlist_simulator": args.sim, "netlist_build_seconds": round(build_seconds, 1),
              "netlist_seconds": round(time.monotonic() - start, 1)}
    (out / f"{stem}.json").write_text(json.dumps(result, indent=1) + "\n")
    print(f"synth ok: {args.config} data cache {cache['cells']} cells ({cache['flops']} flops), {cache['ram_bits']} "
          f"RAM bits in {cache['rams']} RAMs; memory system {system['cells']} cells ({system['flops']} flops), "
          f"{system['ram_bits']} RAM bits; the netlist matches the RTL in all {m.group(1)} cycles of "
          f"{args.vectors} requests per cache")
    return 0


# The chip's units as docs/area.md names them: (module, a pattern of the instance's
# path, the name). Each is counted with everything inside it; a unit's remainder is
# the logic of its own module. Everything else (FIFOs, skid buffers, pipeline
# registers, the FP units' rounding and classification) counts in the unit around it.
# The shader core's parameters among a configuration's (gen.rtl_parameters).
CORE_PARAMETERS = ("Cores", "Threads", "ChunkSize", "IssueLanes", "Registers", "CallDepth", "StackBytes", "SfuUnits",
                   "SfuThreads", "ExpBits", "FracBits")

CHIP_UNITS = [
    ("rpu_chip_cosim_top", r"", "chip"),
    ("rpu_spu", r"", "shader core"),
    ("rpu_ram", r"\.u_code$", "code memory"),
    ("rpu_ram", r"\.u_rf$", "register file bank"),
    ("rpu_ram", r"\.u_return_stack$", "return stack"),
    ("rpu_spu_datapath", r"", "vector datapath"),
    ("rpu_fp_fma", r"", "fma"),
    ("rpu_fp_misc", r"", "misc"),
    ("rpu_fp_misc_core", r"\.u_(from|to)_fp32$", "fp32 conversion"),
    ("rpu_fp_divsqrt", r"", "divsqrt"),
    ("rpu_spu_lsu", r"", "load/store unit"),
    ("rpu_spu_memcheck", r"", "address check"),
    ("rpu_spu_sfu", r"", "special-function unit"),
    ("rpu_cache", r"g_core\[\d+\]\.u_data_cache$", "data cache"),
    ("rpu_cache", r"g_ray_cache\[0\]\.g_pair\[\d+\]\.u_cache$", "node cache"),
    ("rpu_cache", r"g_ray_cache\[1\]\.g_pair\[\d+\]\.u_cache$", "triangle cache"),
    ("rpu_ray_dispatch", r"", "ray dispatch"),
    ("rpu_ray_unit", r"", "ray unit"),
    ("rpu_tu", r"", "traversal unit"),
    ("rpu_iu", r"", "intersection unit"),
    ("rpu_inorder_port", r"", "in-order port"),
    ("rpu_cache_arbiter", r"", "cache arbiter"),
    ("rpu_mem_arbiter", r"", "memory arbiter"),
]


def module_name(rtlil: str) -> str:
    """The source module of a Yosys module name: rpu_fifo for $paramod$<hash>\\rpu_fifo and
    $paramod\\rpu_fifo\\Width=..."""
    parts = rtlil.split("\\")
    return parts[1] if parts[0].startswith("$paramod") else parts[0]


def parse_module_stats(stat: str, cmos: str, netlist: str) -> dict[str, dict]:
    """Per module of a hierarchical Yosys run: its own cells, flops, CMOS transistors and
    RAM bits (without its submodules'), and its submodule instances (type, name).
    `stat` and `cmos` are Yosys' hierarchical `stat` and `stat -tech cmos`; `netlist` is
    its write_verilog output, which names the instances and declares the RAMs."""
    modules = {}
    for name, body in re.findall(r"^=== (.+?) ===\n(.*?)(?=^=== |\Z)", stat, re.M | re.S):
        if name == "design hierarchy":
            continue
        kinds = {m.group(1): int(m.group(2)) for m in re.finditer(r"^\s+(\S+)\s+(\d+)$", body, re.M)
                 if not m.group(1).startswith("Number")}
        modules[name] = {"kinds": kinds}
    for name, body in re.findall(r"^=== (.+?) ===\n(.*?)(?=^=== |\Z)", cmos, re.M | re.S):
        m = re.search(r"Estimated number of transistors:\s+(\d+)", body)
        if name in modules:
            modules[name]["transistors"] = int(m.group(1)) if m else 0
    # write_verilog escapes a name with a backslash and ends it with a space.
    unescape = lambda n: n[1:] if n.startswith("\\") else n  # noqa: E731
    for block in re.split(r"^module ", netlist, flags=re.M)[1:]:
        name = unescape(block.split("(", 1)[0].strip())
        if name not in modules:
            continue
        rams = re.findall(r"^\s*reg \[(\d+):0\] \S+\s+\[(\d+):0\];", block, re.M)
        modules[name]["ram_bits"] = sum((int(w) + 1) * (int(d) + 1) for w, d in rams)
        modules[name]["instances"] = [(unescape(t), unescape(i)) for t, i in
                                      re.findall(r"^\s+(\S+)\s+(\S+)\s+\($", block, re.M)
                                      if unescape(t) in modules]
    for st in modules.values():
        subs = {t for t, _ in st.get("instances", [])}
        own = {k: n for k, n in st["kinds"].items() if k not in subs}
        st["cells"] = sum(own.values())
        st["flops"] = sum(n for k, n in own.items() if "DFF" in k or "DLATCH" in k)
        st.setdefault("ram_bits", 0)
        st.setdefault("transistors", 0)
        st.setdefault("instances", [])
    return modules


def chip_units(modules: dict[str, dict], top: str) -> tuple[list[dict], dict]:
    """The chip's units (CHIP_UNITS) with their instance counts and each instance's
    cells, flops, RAM bits and transistors (everything inside it), in the order of the
    hierarchy; and the chip's totals."""
    totals_of = {}

    def inclusive(name: str) -> dict:
        if name not in totals_of:
            st = modules[name]
            t = {k: st[k] for k in ("cells", "flops", "ram_bits", "transistors")}
            for sub, _ in st["instances"]:
                for k, v in inclusive(sub).items():
                    t[k] += v
            totals_of[name] = t
        return totals_of[name]

    units: dict[tuple, dict] = {}

    def walk(name: str, path: str, depth: int, parent: str) -> None:
        base = module_name(name)
        unit = next((label for mod, pattern, label in CHIP_UNITS
                     if mod == base and re.search(pattern, path)), None)
        if unit is not None:
            key = (parent, unit, name)
            if key not in units:
                units[key] = {"unit": unit, "module": base, "within": parent, "depth": depth, "instances": 0,
                              **inclusive(name)}
            units[key]["instances"] += 1
            parent, depth = unit, depth + 1
        for sub, inst in modules[name]["instances"]:
            walk(sub, f"{path}.{inst}" if path else inst, depth, parent)

    walk(top, "", 0, "")
    # What no unit holds: rpu_top's own logic (the launch and start registers, the stop
    # and done logic, the counters) and its skid buffers; or, of a shader core alone,
    # its own logic (the chunks, the sequencer, the scoreboard, the ways' checks).
    top_label = next(label for mod, _, label in CHIP_UNITS if mod == module_name(top))
    total = inclusive(top)
    rest = dict(total)
    for u in units.values():
        if u["within"] == top_label:
            for k in rest:
                rest[k] -= u["instances"] * u[k]
    # Modules that differ only in an id parameter (a core's CoreId, a cache's CacheId) are
    # one row: the instances of every such module, each instance's numbers their mean
    # (they differ by a few cells, where the id is compared with a constant).
    rows: dict[tuple, dict] = {}
    for u in units.values():
        key = (u["within"], u["unit"])
        if key not in rows:
            rows[key] = {**u, "instances": 0, **{k: 0 for k in rest}}
        rows[key]["instances"] += u["instances"]
        for k in rest:
            rows[key][k] += u["instances"] * u[k]
    result = []
    for row in rows.values():
        result.append({**row, **{k: round(row[k] / row["instances"]) for k in rest}})
    own = ("top-level logic", "rpu_top") if top_label == "chip" else ("the core's own logic", module_name(top))
    result.insert(1, {"unit": own[0], "module": own[1], "within": top_label, "depth": 1, "instances": 1, **rest})
    return result, total


def synth_chip(args) -> int:
    """Yosys synth of a named configuration's chip (rpu_chip_cosim_top: rpu_top with the
    Woop test), or with --unit core of its shader core alone (rpu_spu), RAMs kept as
    memories: cells, flops, RAM bits and transistors per unit and in all from the
    hierarchical run; --issue-lanes sets the core's issue lanes in place of the
    configuration's. With --netlist (the chip only), flattened (and its totals counted
    again), the netlist replays every cycle of a chip_cosim frame and must match the
    RTL's outputs in every bit, and its memory-port writes must rebuild the frame."""
    tables = gen.load(ROOT / "spec")
    resolved = {r["name"]: r for r in tables["resolved"]}
    if args.config not in resolved:
        print(f"flow.py: unknown configuration '{args.config}'; spec/configs.toml has {list(resolved)}",
              file=sys.stderr)
        return 2
    if args.netlist and (not args.cosim or args.unit == "core"):
        print("flow.py: --netlist needs --unit chip and --cosim (the chip_cosim binary)", file=sys.stderr)
        return 2
    config = gen.rtl_parameters(tables, resolved[args.config]["values"])
    if args.issue_lanes:
        config["IssueLanes"] = args.issue_lanes
    if args.unit == "core":
        top, sources = "rpu_spu", rtl_sources()
        params = {k: v for k, v in config.items() if k in CORE_PARAMETERS}
        params["CodeWords"] = args.code_words
    else:
        top, sources = "rpu_chip_cosim_top", [*rtl_sources(), harness_top("chip")]
        params = {**config, "IsectMode": isect_mode("woop"), "CodeWords": args.code_words}
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    stem = f"{args.unit}_{args.config}_lanes{config['IssueLanes']}"
    netlist, hier = out / f"{stem}.v", out / f"{stem}_hier.v"
    stat, cmos = out / f"{stem}_hier.stat", out / f"{stem}_hier.cmos"
    reads = " ".join(str(p) for p in [args.pkg, *sources])
    # Synthesised without -flatten, every module once however often it is instantiated
    # (the default chip's four cores cost one core's time); stat then counts each module
    # alone. Flattened afterwards for the netlist simulation only (the default chip's
    # flat netlist would hold every core and ray unit again): the same gates, and
    # opt_clean drops what only fed outputs nothing reads (so the flat total is lower).
    flatten = ["flatten", "opt_clean", "splitnets", "stat", "stat -tech cmos",
               f"write_verilog -noattr {netlist}"] if args.netlist else []
    script = "; ".join([
        f"read_verilog -sv {reads}",
        f"hierarchy -check -top {top} " + " ".join(f"-chparam {k} {v}" for k, v in params.items()),
        f"synth -top {top} -run begin:fine", *KEEP_RAMS,
        f"tee -q -o {stat} stat", f"tee -q -o {cmos} stat -tech cmos",
        f"write_verilog -noattr {hier}",
        *flatten,
    ])
    start = time.monotonic()
    text = run_yosys(args, script, out / f"{stem}.yosys.log")
    if text is None:
        return 1
    synth_seconds = time.monotonic() - start
    modules = parse_module_stats(stat.read_text(), cmos.read_text(), hier.read_text())
    units, hier_total = chip_units(modules, top)
    # How this run was asked for, paths in the tree relative to it (flow.py area keeps it).
    command = " ".join(["python3", "rtl/flow.py", *(a.replace(f"{ROOT}/", "") for a in sys.argv[1:])])
    result = {"unit": args.unit, "config": args.config, "issue_lanes": config["IssueLanes"], "isect": "woop",
              "command": command, "parameters": params, "units": units, "hierarchical": hier_total,
              "synth_seconds": round(synth_seconds, 1)}
    print(f"ok   yosys {stem} in {synth_seconds:.1f} s: {hier_total['cells']} cells ({hier_total['flops']} flops), "
          f"{hier_total['ram_bits']} RAM bits, {hier_total['transistors']} CMOS transistors")
    if args.netlist:
        flat = parse_stat(text.split("Executing FLATTEN pass")[-1])
        flat["ram_bits"] = sum((int(w) + 1) * (int(d) + 1) for w, d in
                               re.findall(r"^\s*reg \[(\d+):0\] \S+\s+\[(\d+):0\];", netlist.read_text(), re.M))
        del flat["cell_kinds"]
        result["flat"] = flat
        print(f"ok   flattened: {flat['cells']} cells ({flat['flops']} flops), {flat['ram_bits']} RAM bits, "
              f"{flat['transistors']} CMOS transistors")
    for u in units:
        print(f"     {'  ' * u['depth']}{u['unit']:<24} {u['instances']:>3} x {u['cells']:>8} cells "
              f"{u['flops']:>7} flops {u['ram_bits']:>8} RAM bits")
    if args.netlist:
        sim = simulate_chip(args, out, stem, netlist, tables)
        if sim is None:
            return 1
        result.update(sim)
    (out / f"{stem}.json").write_text(json.dumps(result, indent=1) + "\n")
    print(f"synth ok: {args.config} {args.unit} {hier_total['cells']} cells ({hier_total['flops']} flops), "
          f"{hier_total['ram_bits']} RAM bits"
          + (f"; the flattened netlist matches the RTL in all {result['netlist_cycles']} cycles of a "
             f"{result['netlist_frame']} frame and rebuilds its framebuffer" if args.netlist else ""))
    return 0


def simulate_chip(args, out: pathlib.Path, stem: str, netlist: pathlib.Path, tables: dict) -> dict | None:
    """The chip's netlist through every cycle of a chip_cosim frame (the code writes, the
    start and the frame; chip_cosim checks the RTL against the functional model in
    lockstep meanwhile); then the frame rebuilt from the netlist's own memory-port
    writes against the framebuffer the RTL wrote."""
    # The testbench's port widths from the netlist itself (the cores, ray units and code
    # address) and the spec (each stream's bits).
    widths = {m.group(2): int(m.group(1)) + 1 if m.group(1) else 1
              for m in re.finditer(r"^\s*(?:input|output)\s+(?:\[(\d+):0\]\s+)?(\w+);", netlist.read_text(), re.M)}
    bits = stream_bits()
    tb_params = {"Cores": widths["issue_valid_o"], "Ways": widths["retire_valid_o"], "RayUnits": widths["ray_counters_o"] // bits["ray_unit_counters"],
                 "Caches": widths["cache_counters_o"] // bits["cache_counters"],
                 "CodeAddrBits": widths["code_addr_i"], "LaunchBits": bits["launch"], "TuCfgBits": bits["tu_cfg"],
                 "DramReqBits": bits["dram_req"], "DramRspBits": bits["dram_rsp"], "IssueBits": bits["issue"],
                 "RetireBits": bits["retire"], "WritebackBits": bits["writeback"], "FaultBits": bits["fault"],
                 "CoreCountersBits": bits["core_counters"], "RayUnitCountersBits": bits["ray_unit_counters"],
                 "CacheCountersBits": bits["cache_counters"]}
    start = time.monotonic()
    simulate = build_netlist_sim(args, out, stem, netlist, CHIP_NETLIST_TB, "rpu_chip_netlist_tb", tb_params)
    if simulate is None:
        return None
    build_seconds = time.monotonic() - start
    vectors, framebuffer, requests = out / f"{stem}.vec", out / f"{stem}.fb", out / f"{stem}.requests"
    frame = ["--config", args.config, "--isect", "woop", "--scene", args.scene, "--width", args.width,
             "--height", args.height, "--spp", 1, "--max-depth", args.max_depth]
    r = run([args.cosim, *frame, "--write-vectors", vectors, "--write-framebuffer", framebuffer])
    if r.returncode != 0:
        print(f"synth FAIL: {args.cosim} --write-vectors:\n{r.stdout}{r.stderr}")
        return None
    print(f"ok   {r.stdout.strip()}")
    start = time.monotonic()
    r = run([*simulate, f"+vectors={vectors}", f"+requests={requests}"])
    sim_seconds = time.monotonic() - start
    text = r.stdout + r.stderr
    m = re.search(r"netlist ok: (\d+) cycles", text)
    if r.returncode != 0 or not m:
        print(f"synth FAIL: netlist of the {args.config} chip on {vectors}:\n{text[-5000:]}")
        return None
    print(f"ok   netlist: {m.group(0)} in {sim_seconds:.1f} s")
    want = framebuffer.read_bytes()
    got = frame_from_requests(requests.read_text(), len(want), tables)
    if got != want:
        i = next(k for k in range(len(want)) if got[k] != want[k])
        print(f"synth FAIL: the netlist's framebuffer writes differ from the RTL's framebuffer at byte {i} "
              f"(pixel {i // 16}): {got[i]:#04x}, the RTL's {want[i]:#04x}")
        return None
    print(f"ok   the netlist's memory-port writes rebuild the RTL's {len(want) // 16}-pixel framebuffer byte for byte")
    vectors.unlink()
    requests.unlink()
    return {"netlist_cycles": int(m.group(1)), "netlist_simulator": args.sim,
            "netlist_frame": f"{args.scene} {args.width}x{args.height}, 1 spp, max depth {args.max_depth}",
            "netlist_build_seconds": round(build_seconds, 1), "netlist_seconds": round(sim_seconds, 1)}


def frame_from_requests(text: str, size: int, tables: dict) -> bytes:
    """The framebuffer (`size` bytes at the device's framebuffer_base) as the memory-port
    writes in `text` leave it: one request a line, its 32-bit words least significant
    first (sim/rpu_chip_netlist_tb.sv +requests); dram_req's fields from the spec."""
    fields = {f["name"]: f for s in gen.streams.layout(tables, gen.fp_op_bits(tables))["streams"]
              if s["name"] == "dram_req" for f in s["fields"]}
    base = tables["memory_map"]["device"]["framebuffer_base"]
    field = lambda v, name: v >> fields[name]["lsb"] & ((1 << fields[name]["bits"]) - 1)  # noqa: E731
    frame = bytearray(size)
    for line in text.splitlines():
        v = sum(int(w, 16) << (32 * i) for i, w in enumerate(line.split()))
        if not field(v, "write"):
            continue
        addr, mask, data = field(v, "addr"), field(v, "wmask"), field(v, "data")
        for k in range(mask.bit_length()):
            at = addr + 4 * k - base
            if mask >> k & 1 and 0 <= at < size:
                frame[at:at + 4] = (data >> (32 * k) & 0xFFFFFFFF).to_bytes(4, "little")
    return bytes(frame)


def build_netlist_sim(args, out: pathlib.Path, stem: str, netlist: pathlib.Path, tb: pathlib.Path, tb_top: str,
                      params: dict, defines: dict | None = None) -> list | None:
    """Compiles the testbench with the netlist (its parameters and macros); returns the
    command that runs it.

    Verilator by default: Icarus is exact on Yosys netlists but event-driven, and the
    glitches of a multiplier's gate netlist made it take minutes per netlist (fp32 fma:
    12k vectors in 340 s against under a second for the Verilated netlist, which costs
    about 30 s to compile). Verilator 5.006 mis-simulated some netlists without
    splitnets (docs/style.md "What Yosys 0.23 reads"); a mis-simulation shows up as a mismatch here.
    """
    start = time.monotonic()
    if args.sim == "icarus":
        vvp = out / f"{stem}.vvp"
        r = run([args.iverilog, "-g2012", "-I", ROOT / "sim", "-o", vvp, "-s", tb_top,
                 *[f"-D{k}={v}" for k, v in (defines or {}).items()],
                 *[f"-P{tb_top}.{k}={v}" for k, v in params.items()], tb, netlist])
        command = [args.vvp, "-n", vvp]
    else:
        obj = out / f"{stem}.obj"
        shutil.rmtree(obj, ignore_errors=True)
        # The netlist is not lint-clean code (Yosys names, unused outputs); the RTL is
        # linted by rtl.lint. The C++ is compiled at -O0: compile time dominates here.
        env = dict(os.environ)
        if shutil.which("ccache"):
            env["OBJCACHE"] = "ccache"
        r = run([args.verilator, "--binary", "-Wno-fatal", "-Wno-lint", "-Wno-style",
                 "--x-assign", "unique", "--x-initial", "unique", "--top-module", tb_top, f"-I{ROOT / 'sim'}",
                 *[f"-G{k}={v}" for k, v in params.items()],
                 *[f"+define+{k}={v}" for k, v in (defines or {}).items()], "-Mdir", obj, "-j", "1",
                 "-CFLAGS", "-O0", tb, netlist], env=env)
        # Registers and X start random but reproducible (docs/style.md "SystemVerilog").
        command = [obj / f"V{tb_top}", "+verilator+rand+reset+2", "+verilator+seed+1"]
    if r.returncode != 0:
        print(f"synth FAIL: building the {args.sim} netlist simulation:\n{r.stdout[-3000:]}{r.stderr[-3000:]}")
        return None
    print(f"ok   {args.sim} netlist simulation built in {time.monotonic() - start:.1f} s")
    return command


def parse_stat(text: str) -> dict:
    """Cell counts from `stat`, transistors from `stat -tech cmos` (the last report)."""
    reports = text.split("Printing statistics.")
    first = reports[1] if len(reports) > 1 else text
    cells = int(re.search(r"Number of cells:\s+(\d+)", first).group(1))
    kinds = {m.group(1): int(m.group(2)) for m in re.finditer(r"^\s+(\$_\w+_)\s+(\d+)", first, re.M)}
    flops = sum(n for k, n in kinds.items() if "DFF" in k or "SDFF" in k or "DLATCH" in k)
    stats = {"cells": cells, "flops": flops, "cell_kinds": kinds}
    m = re.search(r"Estimated number of transistors:\s+(\d+)", reports[-1])
    if m:
        stats["transistors"] = int(m.group(1))
    return stats


def area(args) -> int:
    """Append synth's results (one JSON file per unit and format) to bench/results/area.json,
    from which scripts/doc-tables makes the tables of docs/area.md."""
    results = pathlib.Path(args.results)
    keep = ("unit", "design", "slots", "packet", "setups", "format", "exponent_bits", "fraction_bits", "cells", "flops",
            "ram_bits", "transistors", "synth_seconds", "netlist_vectors", "netlist_simulator", "netlist_build_seconds",
            "netlist_seconds")
    new = []
    # A chip's or a core's record: its units and totals, the netlist's frame and the
    # command that synthesised it (flow.py synth --unit chip or core).
    keep_chip = ("unit", "config", "issue_lanes", "isect", "units", "hierarchical", "flat", "synth_seconds",
                 "netlist_frame", "netlist_cycles", "netlist_simulator", "netlist_build_seconds", "netlist_seconds", "command")
    # A memory system's record: its data cache alone and the whole (flow.py synth --unit mem).
    keep_mem = ("unit", "config", "data_cache", "memory_system", "netlist_cycles", "netlist_requests_per_cache",
                "netlist_simulator", "netlist_build_seconds", "netlist_seconds")
    for p in sorted(pathlib.Path(getattr(args, "from")).glob("*.json")):
        s = json.loads(p.read_text())
        rec = {"commit": args.commit, "date": time.strftime("%Y-%m-%d")}
        if s["unit"] in ("chip", "core"):
            rec.update({k: s[k] for k in keep_chip if k in s})
        elif s["unit"] == "mem":
            rec["command"] = f"ctest --preset release -L slow -R '^slow\\.synth\\.mem\\.{s['config']}$'"
            rec.update({k: s[k] for k in keep_mem if k in s})
        else:
            ray_unit = s["unit"].startswith(("iu_", "tu_"))
            rec["command"] = ("ctest --preset ci -L slow -R '^slow\\.synth\\.'" if ray_unit
                              else "ctest --preset ci -L synth")
            rec.update({k: s[k] for k in keep if k in s})
        new.append(rec)
    if not new:
        print(f"flow.py area: no synthesis results in {getattr(args, 'from')}; run ctest -L synth "
              "(and -L slow -R synth) first", file=sys.stderr)
        return 1
    append_records(results, new)
    print(f"flow.py area: {len(new)} records appended to {results}; now run scripts/doc-tables")
    return 0


def append_records(results: pathlib.Path, new: list[dict]) -> None:
    """Appends records to a bench/results file, keeping its layout (one record a line)."""
    text = results.read_text()
    end = text.rindex("\n ]\n}")
    lines = "".join(",\n  " + json.dumps(r) for r in new)
    results.write_text(text[:end] + lines + text[end:])
    json.loads(results.read_text())  # still one valid file


def estimate_area(args) -> int:
    """Appends a named configuration's area, estimated from its synthesised units (rtl/estimate.py),
    to bench/results/area.json."""
    results = pathlib.Path(args.results)
    tables = gen.load(ROOT / "spec")
    resolved = {r["name"]: r["values"] for r in tables["resolved"]}
    try:
        rec = estimate.estimate(args.config, resolved, json.loads(results.read_text())["records"], ROOT)
    except estimate.EstimateError as e:
        print(f"flow.py estimate: {e}", file=sys.stderr)
        return 1
    commit = subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"], capture_output=True,
                            text=True, check=True).stdout.strip()
    append_records(results, [{"commit": commit, "date": time.strftime("%Y-%m-%d"),
                              "command": f"python3 rtl/flow.py estimate --config {args.config}", **rec}])
    print(f"flow.py estimate: {args.config}: {rec['mm2']} mm^2 ({rec['logic_mm2']} of logic, {rec['sram_mm2']} of "
          f"SRAM) appended to {results}; now run scripts/doc-tables")
    return 0


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    p = sub.add_parser("lint")
    p.add_argument("--verilator", default=shutil.which("verilator"))
    p.add_argument("--formats", nargs="+", help="lint the format-parameterised units in these formats only")
    p.add_argument("--chips", nargs="+", metavar="CONFIG",
                   help="lint the whole chip (rpu_top) of these named configurations only")
    p.add_argument("--pkg", required=True, help="the generated rpu_pkg.sv")
    p = sub.add_parser("synth")
    p.add_argument("--unit", required=True, help="an FP unit of spec/fp_units.toml, iu, tu, mem, chip or core "
                   "(a configuration's shader core)")
    p.add_argument("--isect", choices=ISECT_MODES, default="woop", help="with --unit iu or tu: the intersection mode")
    p.add_argument("--slots", type=int, default=1,
                   help="with --unit tu: the ray slots (rpu_tu_slots); the netlist keeps that many rays in flight")
    p.add_argument("--pipe", action="store_true",
                   help="with --unit tu: the slots share a node-step pipeline (rpu_tu_pipe)")
    p.add_argument("--setups", type=int, default=2, help="with --pipe: the set-up engines")
    p.add_argument("--packet", type=int, default=1, choices=[1, 2, 4, 8],
                   help="with --pipe: the rays a slot walks together (rpu_tu_pipe's Packet)")
    p.add_argument("--format", help="the number format (not for --unit mem)")
    p.add_argument("--config", default="tiny", help="with --unit mem, chip or core: the named configuration")
    p.add_argument("--issue-lanes", type=int, choices=(1, 2, 4, 8),
                   help="with --unit chip or core: the shader cores' issue lanes (default: the configuration's)")
    p.add_argument("--netlist", action="store_true",
                   help="with --unit chip: simulate the netlist through a chip_cosim frame (--cosim)")
    p.add_argument("--code-words", type=int, default=4096,
                   help="with --unit chip: each core's code memory, as the chip_cosim models are built")
    p.add_argument("--scene", default="cornell", help="with --unit chip --netlist: the frame's scene")
    p.add_argument("--width", type=int, default=8, help="with --unit chip --netlist: the frame's pixels")
    p.add_argument("--height", type=int, default=6, help="with --unit chip --netlist: the frame's pixels")
    p.add_argument("--max-depth", type=int, default=2, help="with --unit chip --netlist: the frame's bounces")
    p.add_argument("--pkg", required=True)
    p.add_argument("--cosim",
                   help="the fp_cosim (for iu iu_cosim, for tu tu_cosim, for mem mem_cosim, for chip chip_cosim) "
                        "binary: writes the vectors (for chip only with --netlist)")
    p.add_argument("--out", required=True)
    p.add_argument("--vectors", type=int, default=10000,
                   help="random vectors, shared by the unit's ops (iu: captured IU tests; tu: rays; mem: requests "
                        "per cache)")
    p.add_argument("--sim", choices=("verilator", "icarus"), default="verilator",
                   help="netlist simulator (default verilator; see build_netlist_sim)")
    p.add_argument("--verilator", default=shutil.which("verilator"))
    p.add_argument("--yosys", default=shutil.which("yosys"))
    p.add_argument("--iverilog", default=shutil.which("iverilog"))
    p.add_argument("--vvp", default=shutil.which("vvp"))
    p = sub.add_parser("area")
    p.add_argument("--from", required=True, help="directory of synth's JSON files")
    p.add_argument("--commit", required=True, help="the commit that was synthesised (git rev-parse --short HEAD)")
    p.add_argument("--results", default=str(ROOT / "bench" / "results" / "area.json"),
                   help="the result file to append to (default bench/results/area.json)")
    p = sub.add_parser("estimate", help="a named configuration's die area from its synthesised units (rtl/estimate.py)")
    p.add_argument("--config", required=True, help="a named configuration of spec/configs.toml")
    p.add_argument("--results", default=str(ROOT / "bench" / "results" / "area.json"),
                   help="the result file to read the units from and append to (default bench/results/area.json)")
    args = ap.parse_args()
    if args.cmd == "synth" and args.unit not in ("chip", "core", "tu") and not args.cosim:
        ap.error("synth needs --cosim (the harness that writes the vectors)")
    return {"lint": lint, "synth": synth, "area": area, "estimate": estimate_area}[args.cmd](args)


if __name__ == "__main__":
    sys.exit(main())
