"""A named configuration's die area, estimated from the units that were synthesised.

A chip too large to synthesise whole here (drpu: eight four-lane cores) is the sum of its
units, each taken from the latest bench/results/area.json record of a unit built with
the same parameters: a shader core from a core record (flow.py synth --unit core) of a
configuration whose cores match, a traversal and an intersection unit from the ray-unit
records (slow.synth.tu_*, slow.synth.iu_*) in the configuration's format, the caches
and the glue (dispatch, memory arbiter, top-level logic) from a chip record whose caches
have the same geometry. Yosys's CMOS transistor count over 4 is the NAND2 equivalents;
the RAM bits (register files, code memories, return stacks, cache data) are SRAM.
docs/area.md "Chips that were not synthesised whole" cites the densities.
"""
from __future__ import annotations

# A 90 nm standard-cell library's maximum density (the Cambridge SoC design course's
# parameters of a 90 nm library), placed and routed at 70% utilisation (our assumption).
NAND2_PER_MM2 = 400_000
UTILISATION = 0.7
# A 6T SRAM cell of 140 F^2 at F = 90 nm, in arrays whose cells take half their area
# (our assumption for decoders, sense amplifiers and redundancy).
SRAM_CELL_UM2 = 140 * 0.090 ** 2
ARRAY_EFFICIENCY = 0.5
TRANSISTORS_PER_NAND2 = 4

CORE_KEYS = ("threads_per_core", "chunk_size", "issue_lanes", "registers", "sfu_units", "sfu_threads", "call_depth",
             "stack_bytes", "format")
CACHE_KEYS = ("bytes", "line_bytes", "ways", "mshrs")


class EstimateError(Exception):
    pass


# Keys the configurations gained after some records were made, with the value every
# configuration had before: what the chip of an older record was built with.
KEYS_ADDED = {"issue_lanes": 1, "tu_slots": 1, "tu_pipe": 0, "tu_setups": 1, "tu_by_tag": 0, "tu_packet": 1,
              "ray_caches": 1, "sfu_threads": 1}


def config_at(root, commit: str, name: str) -> dict | None:
    """Configuration `name` as spec/configs.toml held it at `commit` (a record's, "-dirty"
    ignored), its cache keys flattened as the resolved ones are; None if git has no such
    commit or configuration."""
    import subprocess
    import tomllib
    shown = subprocess.run(["git", "-C", str(root), "show", f"{commit.removesuffix('-dirty')}:spec/configs.toml"],
                           capture_output=True, text=True)
    if shown.returncode != 0:
        return None
    for c in tomllib.loads(shown.stdout).get("config", []):
        if c.get("name") == name:
            flat = dict(KEYS_ADDED)
            for k, value in c.items():
                if isinstance(value, dict):
                    flat.update({f"{k}.{kk}": vv for kk, vv in value.items()})
                else:
                    flat[k] = value
            return flat
    return None


def latest(records: list[dict], match) -> dict | None:
    found = [r for r in records if match(r)]
    return found[-1] if found else None


def chip_unit(record: dict, name: str) -> dict:
    for u in record["units"]:
        if u["unit"] == name and u["depth"] == 1:
            return u
    raise EstimateError(f"chip record {record['commit']} ({record['config']}) has no unit '{name}'")


def estimate(config: str, resolved: dict[str, dict], records: list[dict], root=None) -> dict:
    """The estimate record of configuration `config` (resolved: spec's resolved configurations by name). A
    unit record is matched against its configuration as it was at the record's commit (in the git
    repository at `root`), else as it is now."""
    if config not in resolved:
        raise EstimateError(f"unknown configuration '{config}'; spec/configs.toml has {sorted(resolved)}")
    v = resolved[config]

    def then(r: dict) -> dict:
        """The configuration record `r` was made with."""
        at = config_at(root, r.get("commit", ""), r["config"]) if root is not None else None
        return at if at is not None else resolved[r["config"]]
    rows = []

    def add(unit: str, count: int, src: dict, source: str, note: str = "") -> None:
        rows.append({"unit": unit, "count": count, "cells": src["cells"], "transistors": src["transistors"],
                     "ram_bits": src.get("ram_bits", 0), "source": source, **({"note": note} if note else {})})

    def same_core(r: dict) -> bool:
        if r.get("unit") != "core" or r.get("config") not in resolved:
            return False
        w = then(r)
        lanes = r.get("issue_lanes", w["issue_lanes"])
        return lanes == v["issue_lanes"] and all(w[k] == v[k] for k in CORE_KEYS if k != "issue_lanes")

    core = latest(records, same_core)
    if core is None:
        raise EstimateError(f"no core record matches {config}'s cores ({', '.join(f'{k} = {v[k]}' for k in CORE_KEYS)}): "
                            f"run flow.py synth --unit core --config {config}")
    add("shader core", v["shader_cores"], core["hierarchical"],
        f"{core['config']}'s core, issue_lanes = {core.get('issue_lanes')} ({core['commit']})")

    def tu_kind(r: dict) -> bool:
        """A traversal unit of the configuration's kind, format, packets and set-up engines, any slots."""
        if r.get("unit") != "tu_woop" or r.get("format") != v["format"]:
            return False
        if v["tu_pipe"]:
            return (r.get("setups") == v["tu_setups"] and "node-step pipeline" in r.get("design", "")
                    and r.get("packet", 1) == v["tu_packet"])
        return "pipeline" not in r.get("design", "")

    by_slots = {r.get("slots", 1): r for r in records if tu_kind(r)}  # the latest of each
    kind = (f"a traversal unit in {v['format']}, packets of {v['tu_packet']}, {v['tu_setups']} set-up engines "
            f"(tu_pipe = {v['tu_pipe']})")
    if v["tu_slots"] in by_slots:
        tu = by_slots[v["tu_slots"]]
        add("traversal unit", v["traversal_units"], tu, f"tu_woop {tu['format']}, {tu['design']} ({tu['commit']})")
    elif len(by_slots) >= 2:
        # Slots are copies of one slot's state around a shared pipeline: the unit grows
        # linearly in them, measured between the two largest units synthesised.
        a, b = (by_slots[s] for s in sorted(by_slots)[-2:])
        sa, sb, s = a["slots"], b["slots"], v["tu_slots"]
        unit = {k: round(b[k] + (b[k] - a[k]) * (s - sb) / (sb - sa)) for k in ("cells", "transistors", "ram_bits")}
        add("traversal unit", v["traversal_units"], unit,
            f"tu_woop {b['format']}, packets of {v['tu_packet']}: {s} slots extrapolated from {sa} ({a['commit']}) "
            f"and {sb} ({b['commit']}) linearly", "Yosys ran out of 24 GB on the whole unit")
    else:
        raise EstimateError(f"no record of {kind} with {v['tu_slots']} slots, nor two to extrapolate from")
    iu = latest(records, lambda r: r.get("unit") == "iu_woop" and r.get("format") == v["format"]
                and r.get("design") == "pipeline, one test a cycle")
    if iu is None:
        raise EstimateError(f"no pipelined iu_woop record in {v['format']}")
    add("intersection unit", v["intersection_units"], iu, f"iu_woop {iu['format']}, pipeline ({iu['commit']})")

    def same_caches(r: dict) -> bool:
        if r.get("unit") != "chip" or r.get("config") not in resolved:
            return False
        w = then(r)
        return all(w[f"{c}.{k}"] == v[f"{c}.{k}"] for c in ("node_cache", "triangle_cache", "data_cache")
                   for k in CACHE_KEYS)

    chip = latest(records, same_caches)
    if chip is None:
        raise EstimateError(f"no chip record has {config}'s cache geometry")
    w = then(chip)
    by_tag = "" if w["tu_by_tag"] == v["tu_by_tag"] else (
        f"{chip['config']}'s, whose ray units take their lines in order: the by-tag answers' wait entries not in it")
    # A record from before write_back existed has write-through caches.
    write_back = {c: (w.get(f"{c}.write_back", 0), v[f"{c}.write_back"]) for c in ("node_cache", "triangle_cache", "data_cache")}
    counts = {"node cache": v["ray_caches"], "triangle cache": v["ray_caches"], "data cache": v["shader_cores"]}
    for name, count in counts.items():
        there, here = write_back[name.replace(" ", "_")]
        policy = "" if there == here else (
            f"{chip['config']}'s {'write-back' if there else 'write-through'} cache: "
            f"{'without' if here else 'with'} the write-back's dirty bits and eviction buffer")
        add(name, count, chip_unit(chip, name), f"{chip['config']} chip ({chip['commit']})",
            "; ".join(n for n in (by_tag, policy) if n))
    if not v["tu_by_tag"]:
        add("in-order port", v["traversal_units"], chip_unit(chip, "in-order port"),
            f"{chip['config']} chip ({chip['commit']})")
    # A pair's arbiter takes its ray units' requests; one unit's pass through, no cells.
    pair_units, pair_units_there = v["traversal_units"] // v["ray_caches"], w["traversal_units"] // w["ray_caches"]
    if pair_units > 1:
        note = "" if pair_units == pair_units_there else f"for {pair_units_there} ray units, this chip's for {pair_units}"
        add("cache arbiter", 2 * v["ray_caches"], chip_unit(chip, "cache arbiter"),
            f"{chip['config']} chip ({chip['commit']})", note)
    for name in ("ray dispatch", "memory arbiter", "top-level logic"):
        note = "" if w["shader_cores"] == v["shader_cores"] else f"for {w['shader_cores']} cores"
        held, held_here = w["tu_slots"] * w["tu_packet"], v["tu_slots"] * v["tu_packet"]
        if name == "ray dispatch" and held != held_here:
            note += (f"{'; ' if note else ''}its tables for {held} ray(s) a unit in slots, "
                     f"this chip's for {held_here}")
        add(name, 1, chip_unit(chip, name), f"{chip['config']} chip ({chip['commit']})", note)

    nand2 = sum(r["count"] * r["transistors"] for r in rows) / TRANSISTORS_PER_NAND2
    bits = sum(r["count"] * r["ram_bits"] for r in rows)
    logic_mm2 = nand2 / (NAND2_PER_MM2 * UTILISATION)
    sram_mm2 = bits * SRAM_CELL_UM2 / ARRAY_EFFICIENCY / 1e6
    return {"unit": "estimate", "config": config, "rows": rows,
            "nand2": round(nand2), "ram_bits": bits, "logic_mm2": round(logic_mm2, 1),
            "sram_mm2": round(sram_mm2, 1), "mm2": round(logic_mm2 + sram_mm2, 1),
            "densities": {"nand2_per_mm2": NAND2_PER_MM2, "utilisation": UTILISATION,
                          "sram_cell_um2": round(SRAM_CELL_UM2, 3), "array_efficiency": ARRAY_EFFICIENCY}}
