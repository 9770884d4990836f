#!/usr/bin/env python3
"""Every file the rpu tools read, given as something that is not a regular file.

    special_inputs.py RPU SWEEP_FILE

A FIFO (which blocks a reader until a writer comes), a directory, a character device, a
socket, a loop of symbolic links and a file that fails half way through its read, in
every place a command reads a file: each must end at once in `rpu: error: <what> PATH:
<what it is>` with exit status 1, never in a hang, an internal error or a traceback
(docs/robustness.md, "Files the tools read").
"""
import json
import os
import re
import shutil
import socket
import subprocess
import sys
import tempfile

from outcome import finish

rpu, sweep_file = sys.argv[1], sys.argv[2]
tmp = tempfile.mkdtemp(prefix="rpu-special-")
failures = []

# Each kind: a maker of the path (given its name) and what the message must say.
def fifo(path):
    os.mkfifo(path)


def directory(path):
    os.mkdir(path)


def loop(path):
    other = path + ".other"
    os.symlink(path, other)
    os.symlink(other, path)


def sock(path):
    s = socket.socket(socket.AF_UNIX)
    s.bind(path)
    return s  # kept open while the commands run


def device(path):
    os.symlink("/dev/null", path)


KINDS = {
    "fifo": (fifo, "a FIFO \\(named pipe\\); the tools read only regular files"),
    "directory": (directory, "a directory; the tools read only regular files"),
    "loop": (loop, "a loop of symbolic links"),
    "socket": (sock, "a socket; the tools read only regular files"),
    "device": (device, "a character device; the tools read only regular files"),
}

# (place, the file's extension, the command with {} for the path, what the message calls it)
PLACES = [
    ("render scene file", ".json", ["render", "{}", "-o", "{out}.png"], "the scene file"),
    ("render mesh", ".ply", ["render", "{}", "-o", "{out}.png"], "the scene"),
    ("raycast scene", ".json", ["raycast", "{}", "-o", "{out}.png"], "the scene file"),
    ("tree scene", ".off", ["tree", "{}"], "the scene"),
    ("accel scene", ".stl", ["accel", "{}"], "the scene"),
    ("render --firmware .s", ".s", ["render", "cornell", "--backend", "functional", "--firmware", "{}", "-o", "{out}.png"],
     "the firmware"),
    ("render --firmware .rgen", ".rgen",
     ["render", "cornell", "--backend", "functional", "--firmware", "{}", "-o", "{out}.png"], "the shader"),
    ("render --config", ".toml", ["render", "cornell", "--backend", "functional", "--config", "{}", "-o", "{out}.png"],
     "the configuration file"),
    ("render --compare", ".exr", ["render", "tetra:1", "--width", "8", "--height", "8", "--compare", "{}", "-o",
                                  "{out}.png"], "the image"),
    ("config show", ".toml", ["config", "show", "{}"], "the configuration file"),
    ("fit --base", ".toml", ["fit", "tetra:1", "--min-psnr", "30", "--base", "{}", "-o", "{out}.toml"],
     "the configuration file"),
    ("asm", ".s", ["asm", "{}", "-o", "{out}.rfw"], "the assembly source"),
    ("disasm", ".rfw", ["disasm", "{}"], "the firmware"),
    ("cc", ".rchit", ["cc", "{}", "-o", "{out}.rfw"], "the shader"),
    ("sweep", ".toml", ["sweep", "{}", "-o", "{out}"], "the sweep file"),
]


def run(argv, expect, label):
    try:
        r = subprocess.run(argv, capture_output=True, text=True, timeout=30, stdin=subprocess.DEVNULL)
    except subprocess.TimeoutExpired:
        failures.append(f"{label}: still running after 30 s (it waits on the input)")
        return
    if r.returncode != 1 or not re.search(expect, r.stderr) or "internal error" in r.stderr or "Traceback" in r.stderr:
        failures.append(f"{label}: exit {r.returncode}, stderr {r.stderr.strip()[:300]!r}; expected exit 1 and /{expect}/")


n = 0
for kind, (make, says) in KINDS.items():
    for place, ext, template, what in PLACES:
        n += 1
        path = os.path.join(tmp, f"in{n}{ext}")
        keep = make(path)
        out = os.path.join(tmp, f"out{n}")
        argv = [rpu] + [a.replace("{out}", out).replace("{}", path) for a in template]
        run(argv, f"rpu: error: (.*: )?{what} {re.escape(path)}: {says}", f"{place}, {kind}")
        del keep

# A file that is regular but fails to read (EIO): a scene read from /proc/self/mem.
run([rpu, "render", "/proc/self/mem", "-o", os.path.join(tmp, "mem.png")],
    "rpu: error: the mesh file /proc/self/mem: cannot read: Input/output error", "render a file that fails to read")

# A mesh named by a scene file.
mesh = os.path.join(tmp, "mesh.ply")
os.mkfifo(mesh)
scene = os.path.join(tmp, "with_mesh.json")
with open(scene, "w") as f:
    json.dump({"meshes": [{"file": mesh}]}, f)
run([rpu, "render", scene, "-o", os.path.join(tmp, "m.png")],
    f"rpu: error: {scene}: /meshes/0/file: the mesh file {mesh}: a FIFO", "a scene's mesh, fifo")

# A record inside a sweep directory given to rpu report.
sweep_dir = os.path.join(tmp, "sweep")
r = subprocess.run([rpu, "sweep", sweep_file, "-o", sweep_dir, "--plan"], capture_output=True, text=True)
if r.returncode != 0:
    failures.append(f"rpu sweep --plan {sweep_file}: exit {r.returncode}: {r.stderr.strip()[:300]}")
else:
    with open(os.path.join(sweep_dir, "plan.json")) as f:
        first = json.load(f)["points"][0]["id"]
    record = os.path.join(sweep_dir, "points", first + ".json")
    os.makedirs(os.path.dirname(record), exist_ok=True)
    report = [rpu, "report", sweep_dir, "-o", os.path.join(tmp, "report.html")]
    os.mkfifo(record)
    run(report, f"rpu: error: {re.escape(record)}: the point's record is not a regular file", "report, a fifo record")
    os.remove(record)
    # Records that are not what rpu sweep writes: named, never a traceback.
    for content, says in (('{"id": "x", "row', "is not JSON that rpu sweep wrote \\(Unterminated string"),
                          ('{"row": NaN}', "is not JSON that rpu sweep wrote \\(NaN is not a JSON number\\)"),
                          ("[1, 2]", "is a JSON list, not an object"),
                          ('{"row": {}, "point": {}}', "the record's point has no fidelity")):
        with open(record, "w") as f:
            f.write(content)
        run(report, f"rpu: error: {re.escape(record)}: (the point.s record )?{says}", f"report, a record {content!r}")
    os.remove(record)
    plan_path = os.path.join(sweep_dir, "plan.json")
    with open(plan_path) as f:
        plan_text = f.read()
    with open(plan_path, "w") as f:
        f.write(plan_text.replace("[", "[NaN, ", 1))
    run(report, f"rpu: error: {re.escape(plan_path)}: the sweep's plan is not JSON", "report, NaN in the plan")

shutil.rmtree(tmp)
finish(failures, f"{n + 8} special inputs refused at once with the file named")
