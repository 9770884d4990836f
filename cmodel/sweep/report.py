"""rpu report: a sweep directory (rpu sweep -o DIR) as one page of tables and plots.

Built into the rpu binary, with spec/doc_blocks.py beside it, and run by `rpu report`
with Debian's /usr/bin/python3 and python3-matplotlib (docs/sweeps.md, "Reports"):

    report.py DIR html                            -> the self-contained HTML page on stdout
    report.py DIR md PICTURES_DIR REL PAGE COMMAND -> PAGE with its generated block replaced
                                                     (a new page if there is none) on stdout,
                                                     the pictures as PNG files in
                                                     PICTURES_DIR, linked as REL/NAME.png

Reads DIR/plan.json and each point's record DIR/points/ID.json; every number shown is a
field of a record. Points not run yet are left out and counted.
"""
import base64
import collections
import html
import io
import json
import math
import os
import stat
import sys

import doc_blocks
import matplotlib

matplotlib.use("Agg")
import matplotlib.image as mpimg  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.ticker import EngFormatter, NullFormatter  # noqa: E402

# The source the page's generated block names (spec/doc_blocks.py).
SOURCE = "rpu report"
FIDELITIES = ["reference", "functional", "cycle", "rtl"]
# Plots read in print too: one colour per format, one marker per intersection test.
MARKERS = {"woop": "o", "watertight": "s"}
IMAGES_PER_ROW = 8


class BadInput(Exception):
    """A file of the sweep directory that is not what rpu sweep writes; the message names it."""


def read_object(path, what):
    """The JSON object in the regular file `path` (rpu sweep writes no NaN or Infinity)."""
    try:
        mode = os.stat(path).st_mode
    except OSError as e:
        raise BadInput(f"{path}: {what}: {e.strerror}")
    if not stat.S_ISREG(mode):
        raise BadInput(f"{path}: {what} is not a regular file; the tools read only regular files")

    def refuse(name):
        raise ValueError(f"{name} is not a JSON number")

    try:
        with open(path, encoding="utf-8") as f:
            value = json.load(f, parse_constant=refuse)
    except (OSError, UnicodeDecodeError, ValueError) as e:
        raise BadInput(f"{path}: {what} is not JSON that rpu sweep wrote ({e})")
    if not isinstance(value, dict):
        raise BadInput(f"{path}: {what} is a JSON {type(value).__name__}, not an object")
    return value


def field(obj, key, kind, path, what):
    value = obj.get(key)
    if not isinstance(value, kind):
        raise BadInput(f"{path}: {what} has no \"{key}\" of the kind rpu sweep writes")
    return value


def load(directory):
    plan_path = os.path.join(directory, "plan.json")
    plan = read_object(plan_path, "the sweep's plan")
    points = field(plan, "references", list, plan_path, "the plan") + field(plan, "points", list, plan_path, "the plan")
    records, missing = [], 0
    for point in points:
        if not isinstance(point, dict) or not isinstance(point.get("id"), str):
            raise BadInput(f"{plan_path}: a point without an id: {json.dumps(point)[:200]}")
        path = os.path.join(directory, "points", point["id"] + ".json")
        if not os.path.lexists(path):
            missing += 1
            continue
        record = read_object(path, "the point's record")
        field(record, "row", dict, path, "the record")
        if field(record, "point", dict, path, "the record").get("fidelity") not in FIDELITIES:
            raise BadInput(f"{path}: the record's point has no fidelity of {', '.join(FIDELITIES)}")
        records.append(record)
    return plan, records, missing


def scene_name(scene):
    return os.path.basename(scene) if os.path.isabs(scene) else scene


def size(r):
    return f"{r['width']}x{r['height']}"


def number(value, digits=1):
    if value is None:
        return "—"
    if isinstance(value, float):
        return f"{value:.{digits}f}"
    return f"{value:,}"


def format_order(rows):
    """Formats from the widest fraction to the narrowest, as the rows name them."""
    seen = {}
    for r in rows:
        if r["format"]:
            seen[r["format"]] = r
    return sorted(seen, key=lambda f: (-fraction_bits(f), f))


def fraction_bits(name):
    known = {"fp32": 23, "e8m15": 15, "rpu24": 16, "bf16": 7, "fp16": 10}
    if name in known:
        return known[name]
    if name.upper().startswith("E") and "M" in name.upper():
        return int(name.upper().split("M")[1])
    return 0


def colours(formats):
    cmap = plt.get_cmap("tab10")
    return {f: cmap(i % 10) for i, f in enumerate(formats)}


def psnr_value(r):
    """PSNR for plotting: identical images (null) as 160 dB, above every measured value."""
    return 160.0 if r["psnr_db"] is None else r["psnr_db"]


def pareto(points):
    """The (cycles, psnr) points no other beats on both: fewer cycles and more PSNR."""
    front, best = [], -math.inf
    for c, p in sorted(points, key=lambda x: (x[0], -x[1])):
        if p > best:
            front.append((c, p))
            best = p
    return front


def figure_psnr_cycles(rows, scenes, formats, colour):
    timed = [r for r in rows if r["cycles"] is not None]
    if not timed:
        return None
    cols = min(3, len(scenes))
    grid_rows = (len(scenes) + cols - 1) // cols
    fig, axes = plt.subplots(grid_rows, cols, figsize=(4.2 * cols, 3.3 * grid_rows), squeeze=False)
    for ax in axes.flat[len(scenes):]:
        ax.axis("off")
    for ax, scene in zip(axes.flat, scenes):
        mine = [r for r in timed if r["scene"] == scene]
        if not mine:
            continue
        for r in mine:
            ax.scatter(r["cycles"], psnr_value(r), color=colour[r["format"]], marker=MARKERS.get(r["isect"], "x"),
                       s=30, zorder=3)
        front = pareto([(r["cycles"], psnr_value(r)) for r in mine])
        if front:
            ax.step([c for c, _ in front], [p for _, p in front], where="post", color="crimson", lw=1,
                    label="Pareto front", zorder=2)
        cycles = [r["cycles"] for r in mine]
        if max(cycles) > 10 * min(cycles):
            ax.set_xscale("log")
            ax.xaxis.set_minor_formatter(NullFormatter())
        ax.xaxis.set_major_formatter(EngFormatter())
        ax.set_title(scene_name(scene), fontsize=9)
        ax.set_xlabel("cycles per frame")
        ax.set_ylabel("PSNR (dB)")
        ax.grid(alpha=0.3)
    legend(axes.flat[0], formats, colour, extra_front=True)
    fig.tight_layout()
    return fig


def legend(ax, formats, colour, extra_front=False):
    handles = [plt.Line2D([], [], color=colour[f], marker="o", ls="", label=f) for f in formats]
    handles += [plt.Line2D([], [], color="grey", marker=m, ls="", label=k) for k, m in MARKERS.items()]
    if extra_front:
        handles.append(plt.Line2D([], [], color="crimson", lw=1, label="Pareto front"))
    ax.legend(handles=handles, fontsize=7, loc="best")


def figure_area_psnr(rows, scenes, formats, colour):
    sized = [r for r in rows if r["datapath_cells"] is not None and r["fidelity"] == "functional"]
    if not sized:
        return None
    fig, ax = plt.subplots(figsize=(6, 3.6))
    for scene in scenes:
        mine = sorted((r for r in sized if r["scene"] == scene), key=lambda r: r["datapath_cells"])
        for isect, marker in MARKERS.items():
            line = [r for r in mine if r["isect"] == isect]
            if line:
                ax.plot([r["datapath_cells"] for r in line], [psnr_value(r) for r in line], color="grey", lw=0.6)
        for r in mine:
            ax.scatter(r["datapath_cells"], psnr_value(r), color=colour[r["format"]], marker=MARKERS.get(r["isect"], "x"),
                       s=30, zorder=3)
            ax.annotate(scene_name(scene), (r["datapath_cells"], psnr_value(r)), fontsize=6, alpha=0.6,
                        xytext=(3, 2), textcoords="offset points")
    ax.set_xlabel("datapath cells (Yosys: FP units + IU + TU)")
    ax.set_ylabel("PSNR (dB)")
    ax.grid(alpha=0.3)
    legend(ax, [f for f in formats if any(r["format"] == f for r in sized)], colour)
    fig.tight_layout()
    return fig


def figure_host_seconds(rows, scenes):
    levels = [f for f in FIDELITIES if any(r["fidelity"] == f and r["host_seconds"] is not None for r in rows)]
    if not levels:
        return None
    fig, ax = plt.subplots(figsize=(6, 3.6))
    cmap = plt.get_cmap("tab10")
    for i, scene in enumerate(scenes):
        xs, ys = [], []
        for j, level in enumerate(levels):
            for r in rows:
                if r["scene"] == scene and r["fidelity"] == level and r["host_seconds"] is not None:
                    xs.append(j + (i - len(scenes) / 2) * 0.06)
                    ys.append(r["host_seconds"])
        ax.scatter(xs, ys, color=cmap(i % 10), s=14, label=scene_name(scene))
    ax.set_xticks(range(len(levels)), levels)
    ax.set_yscale("log")
    ax.set_ylabel("host seconds per point")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    return fig


def figure_leaks(rows, formats):
    checked = [r for r in rows if r["leak_rays"]]
    if not checked:
        return None
    fig, ax = plt.subplots(figsize=(6, 3.2))
    width = 0.38
    shown = [f for f in formats if any(r["format"] == f for r in checked)]
    for k, isect in enumerate(MARKERS):
        rates = []
        for f in shown:
            mine = [r for r in checked if r["format"] == f and r["isect"] == isect]
            rays = sum(r["leak_rays"] for r in mine)
            rates.append(100.0 * sum(r["leaks"] for r in mine) / rays if rays else float("nan"))
        ax.bar([i + (k - 0.5) * width for i in range(len(shown))], rates, width, label=isect)
    ax.set_xticks(range(len(shown)), shown)
    ax.set_ylabel("leaked rays (%)")
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3, axis="y")
    fig.tight_layout()
    return fig


def figure_images(directory, scene, rows, references, formats, selected):
    """The reference, then each format's image (functional where there is one), then each
    selection's, over its difference map."""
    reference = next((r for r in references if r["scene"] == scene), None)
    shown = []
    for f in formats:
        for isect in MARKERS:
            cands = [r for r in rows if r["scene"] == scene and r["format"] == f and r["isect"] == isect]
            cands.sort(key=lambda r: FIDELITIES.index(r["fidelity"]))
            if cands:
                shown.append(cands[0])
    selections = {}
    for r in sorted((r for r in selected if r["scene"] == scene), key=lambda r: FIDELITIES.index(r["fidelity"])):
        selections.setdefault(r["select"], r)
    shown += selections.values()
    if reference is None or not shown:
        return None
    # Rows of at most IMAGES_PER_ROW pictures, each over its difference map; the
    # reference and the key open the first.
    cols = min(len(shown), IMAGES_PER_ROW) + 1
    bands = (len(shown) + IMAGES_PER_ROW - 1) // IMAGES_PER_ROW
    fig, axes = plt.subplots(2 * bands, cols, figsize=(1.9 * cols, 3.6 * bands), squeeze=False)
    for ax in axes.flat:
        ax.axis("off")
    axes[0][0].imshow(mpimg.imread(os.path.join(directory, "images", reference["id"] + ".png")))
    axes[0][0].set_title("reference", fontsize=7)
    axes[1][0].text(0.5, 0.5, "difference\n(false colour,\nfull at 1/8)", ha="center", va="center", fontsize=7)
    for k, r in enumerate(shown):
        band, col = divmod(k, IMAGES_PER_ROW)
        top, bottom = axes[2 * band][col + 1], axes[2 * band + 1][col + 1]
        top.imshow(mpimg.imread(os.path.join(directory, "images", r["id"] + ".png")))
        what = f"{r['format']} {r['isect']}" if r["select"] == "1" else f"select {r['select']}"
        top.set_title(f"{what}\n{number(r['psnr_db'])} dB", fontsize=7)
        bottom.imshow(mpimg.imread(os.path.join(directory, "images", r["id"] + ".diff.png")))
    fig.suptitle(scene_name(scene), fontsize=9)
    fig.tight_layout()
    return fig


def table(rows):
    head = ["scene", "triangles", "size", "transform", "fidelity", "config", "format", "isect", "select", "PSNR dB", "max error", "dark dots", "self-hits", "tree nodes",
            "nodes / ray", "tests / ray", "hit mismatches", "leaks", "cycles", "fps", "datapath cells", "host s"]
    out = [head]
    for r in rows:
        leaks = "—" if r["leak_rays"] is None else f"{r['leaks']} / {r['leak_rays']}"
        hits = "—" if r["primary_rays"] is None else f"{r['hit_mismatches']} / {r['primary_rays']}"
        config = r["config"] + (f" ({r['set']})" if r["set"] else "")
        psnr = ("refused" if r["error"] is not None else "identical" if r["psnr_db"] is None
                else number(r["psnr_db"]))
        out.append([scene_name(r["scene"]), number(r["triangles"]), size(r), r["transform"] or "—", r["fidelity"], config,
                    r["format"], r["isect"], "—" if r["select"] == "1" else r["select"], psnr,
                    number(r["max_error"], 4), number(r.get("dark_dots")), number(r.get("self_hits")),
                    number(r.get("tree_nodes")),
                    number(r.get("nodes_per_ray")), number(r.get("tests_per_ray")),
                    hits, leaks, number(r["cycles"]), number(r["fps"]), number(r["datapath_cells"]),
                    number(r["host_seconds"], 2)])
    return out


# The extremes (docs/sweeps.md, "Extremes"): a transformed scene passes when its point
# renders within 1 dB of the same point untransformed; a kind of extreme ray passes when
# at most 2% of its rays disagree with the fp64 trace.
TRANSFORM_DB = 1.0
RAY_SHARE = 0.02
EXTREMES_TITLE = ("Extremes, pass or fail per format and test: a transformed scene within "
                  f"{TRANSFORM_DB:g} dB of the same point untransformed; extreme rays with at most "
                  f"{100 * RAY_SHARE:g}% disagreeing with the fp64 trace")
RAY_KINDS = [("axis", "axis-parallel rays"), ("grazing", "grazing rays"), ("surface", "rays from a surface")]


def twin_key(r, transform, select=None):
    return (r["scene"], r["width"], r["height"], transform, r["fidelity"], r["config"], r["set"], r["format"],
            r["isect"], r["firmware"], r["select"] if select is None else select, r["spp"])


def extremes(rows, formats):
    """{label: {(format, isect): (failed, points)}} for every transform and ray kind."""
    by_key = {twin_key(r, r["transform"]): r for r in rows}
    out = {}
    for r in rows:
        if r["transform"]:
            twin = by_key.get(twin_key(r, ""))
            if twin is None:
                continue
            ok = (r["error"] is None and twin["error"] is None
                  and psnr_value(r) >= psnr_value(twin) - TRANSFORM_DB)
            cell = out.setdefault(r["transform"], {}).setdefault((r["format"], r["isect"]), [0, 0])
        else:
            ok = None
        if ok is not None:
            cell[0] += 0 if ok else 1
            cell[1] += 1
        # A selection changes the image, not the units a ray check runs through.
        if r["transform"] or r["error"] is not None or r["select"] != "1":
            continue
        for kind, label in RAY_KINDS:
            rays = r.get(f"{kind}_rays")
            if not rays:
                continue
            cell = out.setdefault(label, {}).setdefault((r["format"], r["isect"]), [0, 0])
            cell[0] += 0 if r[f"{kind}_mismatches"] <= RAY_SHARE * rays else 1
            cell[1] += 1
    return out


def extremes_table(rows, formats):
    table = extremes(rows, formats)
    if not table:
        return None
    isects = [i for i in MARKERS if any(r["isect"] == i for r in rows)]
    head = ["extreme"] + [f"{f} {i}" for f in formats for i in isects]
    out = [head]
    for label, cells in table.items():
        line = [label]
        for f in formats:
            for i in isects:
                failed, points = cells.get((f, i), (None, 0))
                line.append("—" if not points else "pass" if failed == 0 else f"FAIL ({failed} of {points})")
        out.append(line)
    return out


# Selected ray tracing (docs/selection.md): each selected point beside its twin, the same
# point tracing every pixel.
SELECTION_TITLE = ("Selected ray tracing: the rays and cycles saved and the PSNR lost, each selected point against "
                   "the same point tracing every pixel (its twin); points labelled threshold:key")


def selection_pairs(rows):
    """[(selected row, twin row)] for every selected point whose twin rendered."""
    by_key = {twin_key(r, r["transform"]): r for r in rows if r["error"] is None}
    pairs = []
    for r in rows:
        if r["select"] == "1" or r["error"] is not None:
            continue
        twin = by_key.get(twin_key(r, r["transform"], "1"))
        if twin is not None and r["rays"] and twin["rays"]:
            pairs.append((r, twin))
    return pairs


def share_saved(r, twin, field):
    if r[field] is None or not twin[field]:
        return None
    return 100.0 * (1.0 - r[field] / twin[field])


def psnr_lost(r, twin):
    if r["psnr_db"] is None or twin["psnr_db"] is None:
        return None
    return twin["psnr_db"] - r["psnr_db"]


def figure_selection(pairs, scenes):
    """PSNR against the rays saved and, for timed points, the cycles saved. The twins
    themselves render near the reference (their PSNR is in the table), so the PSNR lost
    is read off the y axis from there."""
    plotted = [(r, t) for r, t in pairs if r["psnr_db"] is not None]
    if not plotted:
        return None
    timed = [(r, t) for r, t in plotted if share_saved(r, t, "cycles") is not None]
    panels = [("rays", "rays saved (%)", plotted)] + ([("cycles", "cycles saved (%)", timed)] if timed else [])
    fig, axes = plt.subplots(1, len(panels), figsize=(5.2 * len(panels) + 1.4, 3.8), squeeze=False)
    cmap = plt.get_cmap("tab10")
    blocks = sorted({int(r["select"].split(":")[0]) for r, _ in plotted})
    block_marker = {b: m for b, m in zip(blocks, "os^Dv<>ph*")}
    shown = [s for s in scenes if any(r["scene"] == s for r, _ in plotted)]
    for ax, (field, label, mine) in zip(axes[0], panels):
        # One point per selection and scene: the functional and cycle points agree on
        # rays and PSNR.
        seen = set()
        for r, t in mine:
            if (r["scene"], r["width"], r["height"], r["select"], field) in seen:
                continue
            seen.add((r["scene"], r["width"], r["height"], r["select"], field))
            x, y = share_saved(r, t, field), r["psnr_db"]
            ax.scatter(x, y, color=cmap(shown.index(r["scene"]) % 10),
                       marker=block_marker[int(r["select"].split(":")[0])], s=30, zorder=3)
            ax.annotate(":".join(r["select"].split(":")[1:]).replace("material", "m").replace("primitive", "p"),
                        (x, y), fontsize=6, alpha=0.7, xytext=(3, 2), textcoords="offset points")
        ax.set_xlabel(label)
        ax.set_ylabel("PSNR against the reference (dB)")
        ax.grid(alpha=0.3)
    handles = [plt.Line2D([], [], color=cmap(i % 10), marker="o", ls="", label=scene_name(s))
               for i, s in enumerate(shown)]
    handles += [plt.Line2D([], [], color="grey", marker=block_marker[b], ls="", label=f"{b}x{b} blocks")
                for b in blocks]
    fig.legend(handles=handles, fontsize=7, loc="center right")
    fig.tight_layout(rect=(0, 0, 0.86, 1))
    return fig


def selection_table(pairs):
    if not pairs:
        return None
    out = [["scene", "size", "fidelity", "config", "format", "select", "rays", "rays saved", "PSNR dB",
            "PSNR lost dB", "cycles saved"]]
    for r, t in pairs:
        config = r["config"] + (f" ({r['set']})" if r["set"] else "")
        rays, cycles, lost = share_saved(r, t, "rays"), share_saved(r, t, "cycles"), psnr_lost(r, t)
        out.append([scene_name(r["scene"]), size(r), r["fidelity"], config, r["format"], r["select"], number(r["rays"]),
                    f"{rays:.1f}%", number(r["psnr_db"]), number(lost, 2),
                    "—" if cycles is None else f"{cycles:.1f}%"])
    return out


def html_table(cells):
    out = ["<table>", "<tr>" + "".join(f"<th>{html.escape(c)}</th>" for c in cells[0]) + "</tr>"]
    out += ["<tr>" + "".join(f"<td>{html.escape(c)}</td>" for c in row) + "</tr>" for row in cells[1:]]
    return out + ["</table>"]


def md_table(cells, text_columns, numbers="--:"):
    """A Markdown table whose first text_columns columns are left-aligned."""
    rule = "|" + "|".join("---" if i < text_columns else numbers for i in range(len(cells[0]))) + "|"
    return ["| " + " | ".join(cells[0]) + " |", rule] + ["| " + " | ".join(row) + " |" for row in cells[1:]]


def png_bytes(fig):
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=110, metadata={"Software": None})
    plt.close(fig)
    return buf.getvalue()


def page_with(page: str, block: str) -> str:
    """The Markdown page `page` with its rpu report block replaced, or a new page with one."""
    if not os.path.exists(page):
        return f"# Sweep report\n\n{doc_blocks.begin(SOURCE)}\n{block}{doc_blocks.END}\n"
    with open(page) as f:
        return doc_blocks.replace(f.read(), SOURCE, block, f"-o {page}")


def main():
    directory, mode = sys.argv[1], sys.argv[2]
    if mode == "md":
        # A page with no block to replace is refused before anything is drawn.
        pictures, rel, page, command = sys.argv[3:7]
        try:
            page_with(page, "")
        except doc_blocks.DocBlockError as e:
            print(f"rpu: error: {e}", file=sys.stderr)
            sys.exit(2)
    try:
        plan, records, missing = load(directory)
    except BadInput as e:
        print(f"rpu: error: {e}", file=sys.stderr)
        sys.exit(2)
    rows = [r["row"] for r in records if r["point"]["fidelity"] != "reference"]
    references = [r["row"] for r in records if r["point"]["fidelity"] == "reference"]
    for r in references + rows:
        r.setdefault("transform", "")
        r.setdefault("error", None)
        r.setdefault("select", "1")
    # The plots show the untransformed points that rendered and traced every pixel, the
    # extremes and the selections have their own,
    # at the image size most of those points have (a grid of another size, such as the
    # selections' twins, would mix frames of different cost in one plot).
    plain = [r for r in rows if r["error"] is None and not r["transform"] and r["select"] == "1"]
    sizes = collections.Counter(size(r) for r in plain)
    main_size = sizes.most_common(1)[0][0] if sizes else None
    plotted = [r for r in plain if size(r) == main_size]
    plain_references = [r for r in references if not r["transform"] and size(r) == main_size]
    scenes = list(dict.fromkeys(r["scene"] for r in references + rows))
    formats = format_order(rows)
    colour = colours(formats)
    commits = sorted({r["render"]["run"]["commit"] for r in records if r.get("render", {}).get("run")})
    order = {s: i for i, s in enumerate(scenes)}
    rows.sort(key=lambda r: (order[r["scene"]], formats.index(r["format"]), r["isect"], r["config"], r["set"],
                             FIDELITIES.index(r["fidelity"]), r["spp"], r["select"] != "1", r["select"]))
    pairs = selection_pairs(rows)

    figures = [
        ("psnr-cycles", "PSNR against cycles per frame, by format (cycle and rtl points; the Pareto front in red)",
         figure_psnr_cycles(plotted, scenes, formats, colour)),
        ("area-psnr", "Datapath area against PSNR (functional points; formats without a synthesis are left out)",
         figure_area_psnr(plotted, scenes, formats, colour)),
        ("host-seconds", "Host seconds per point by fidelity level", figure_host_seconds(plain_references + plotted, scenes)),
        ("leaks", "Rays leaking out of the scenes' closed meshes, by format and intersection test",
         figure_leaks(plotted, formats)),
        ("selection", SELECTION_TITLE, figure_selection(pairs, scenes)),
    ]
    for scene in scenes:
        figures.append((f"images-{len(figures) - 4}", f"{scene_name(scene)}: images and difference maps",
                        figure_images(directory, scene, plotted, plain_references, formats,
                                      [r for r, _ in pairs if not r["transform"]])))
    figures = [(name, title, png_bytes(fig)) for name, title, fig in figures if fig is not None]

    summary = (f"{len(records)} points of sweep '{plan['sweep']}' ({len(references)} references)"
               + (f", {missing} not run yet" if missing else "")
               + f"; rpu at {', '.join(c[:12] for c in commits)}")
    cells = table(rows)
    extremes_cells = extremes_table(rows, formats)
    selection_cells = selection_table(pairs)
    if mode == "html":
        out = ["<!DOCTYPE html>", "<html><head><meta charset='utf-8'>",
               f"<title>rpu sweep {html.escape(plan['sweep'])}</title>",
               "<style>body{font-family:sans-serif;margin:2em;max-width:80em}table{border-collapse:collapse;"
               "font-size:80%}td,th{border:1px solid #ccc;padding:2px 6px;text-align:right}"
               "td:nth-child(-n+6),th{text-align:left}img{max-width:100%}</style></head><body>",
               f"<h1>Sweep {html.escape(plan['sweep'])}</h1>", f"<p>{html.escape(summary)}</p>"]
        for name, title, data in figures:
            out.append(f"<h2>{html.escape(title)}</h2>")
            out.append(f"<img alt='{name}' src='data:image/png;base64,{base64.b64encode(data).decode()}'>")
        for title, table_cells in [(EXTREMES_TITLE, extremes_cells), (SELECTION_TITLE, selection_cells),
                                   ("Every point", cells)]:
            if table_cells:
                out += [f"<h2>{html.escape(title)}</h2>"] + html_table(table_cells)
        out.append("</body></html>")
        sys.stdout.write("\n".join(out) + "\n")
        return
    os.makedirs(pictures, exist_ok=True)
    out = [summary + ".", ""]
    # The measured rows beside the pictures: the data the table is made of.
    with open(os.path.join(pictures, "rows.json.tmp"), "w") as f:
        json.dump({"sweep": plan["sweep"], "commits": commits, "rows": references + rows}, f, indent=1)
        f.write("\n")
    os.replace(os.path.join(pictures, "rows.json.tmp"), os.path.join(pictures, "rows.json"))
    for name, title, data in figures:
        path = os.path.join(pictures, name + ".png")
        with open(path + ".tmp", "wb") as f:
            f.write(data)
        os.replace(path + ".tmp", path)
        out += [f"**{title}**", "", f"![{title}]({rel}/{name}.png)", ""]
    if extremes_cells:
        out += [f"**{EXTREMES_TITLE}**", ""] + md_table(extremes_cells, 1, ":-:") + [""]
    if selection_cells:
        out += [f"**{SELECTION_TITLE}**", ""] + md_table(selection_cells, 6) + [""]
    out += md_table(cells, 9)
    sys.stdout.write(page_with(page, "\n".join(out) + f"\n\nMade by `{command}`.\n"))


main()
