#!/usr/bin/env python3
"""rpu render and rpu cc with -D, -I and --spec-constant (docs/shaders.md): the values
reach the firmware, a compile from the cache warns as the first compile did, and the
cache tells compiles with different values apart.

    spec_constants.py RPU SOURCE_DIR WORKDIR
"""
import os
import shutil
import subprocess
import sys

from outcome import finish

rpu, source, work = sys.argv[1], sys.argv[2], sys.argv[3]
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
env = dict(os.environ, RPU_CACHE_DIR=os.path.join(work, "cache"))
failures = []
program = os.path.join(source, "tests/glsl/programs/spec_constants/raygen.rgen")
shaders = [program, os.path.join(source, "firmware/glsl/whitted.rchit"),
           os.path.join(source, "firmware/glsl/background.rmiss")]
warning = "rpu: warning: " + program + ": specialization constant OFFSET (constant_id 7) keeps its default 5"


def run(*args):
    return subprocess.run([rpu, *args], capture_output=True, text=True, env=env)


def render(name, *options):
    out = os.path.join(work, name + ".png")
    r = run("render", "tetra:1", "--backend", "functional", "--width", "1", "--height", "1", "--spp", "1",
            "--firmware", *shaders, *options, "-o", out)
    if r.returncode != 0:
        failures.append(f"{name}: status {r.returncode}: {r.stderr[-400:]}")
        return b"", r.stderr
    with open(out, "rb") as f:
        return f.read(), r.stderr


# PNG (no time in the file): x = STEPS * SCALE = 0.2 or 0.3.
two, first = render("two", "--spec-constant", "0=2", "--spec-constant", "1=0.1")
again, second = render("two_again", "--spec-constant", "0=2", "--spec-constant", "1=0.1")
three, _ = render("three", "--spec-constant", "0=3", "--spec-constant", "1=0.1")
for name, text in (("the compile", first), ("the cached compile", second)):
    if warning not in text:
        failures.append(f"{name} does not warn of the default OFFSET: {text[-400:]}")
if two != again:
    failures.append("the cached firmware renders another image than the compiled one")
if two == three:
    failures.append("STEPS = 2 and STEPS = 3 render the same image: the value did not reach the firmware, "
                    "or the cache ran the firmware compiled for the other")

r = run("cc", *shaders, "-o", os.path.join(work, "s.rfw"), *[f"--spec-constant={c}" for c in ("0=1", "1=0.5", "2=false", "7=1")])
if r.returncode != 0 or "warning" in r.stderr:
    failures.append(f"rpu cc with every constant given: status {r.returncode}, {r.stderr[-300:]}")

refusals = [
    (["-D", "9X=1"], "-D 9X=1: '9X' is not a macro name"),
    (["-I", os.path.join(work, "none")], "-I " + os.path.join(work, "none") + ": not a directory"),
    (["--spec-constant", "x=1"], "--spec-constant x=1: expected ID=VALUE"),
    (["--spec-constant", "0=1", "--spec-constant", "0=2"], "--spec-constant 0=2: constant_id 0 is given twice"),
]
for options, message in refusals:
    r = run("cc", *shaders, "-o", os.path.join(work, "never.rfw"), *options)
    if r.returncode != 1 or message not in r.stderr:
        failures.append(f"rpu cc {' '.join(options)}: status {r.returncode}, {r.stderr[-300:]!r}, expected {message!r}")
r = run("render", "tetra:1", "--backend", "functional", "--firmware", os.path.join(source, "firmware/whitted.s"),
        "--spec-constant", "0=1", "-o", os.path.join(work, "never.png"))
if r.returncode != 1 or "for GLSL shaders, and --firmware names none" not in r.stderr:
    failures.append(f"--spec-constant with assembly firmware: status {r.returncode}, {r.stderr[-300:]!r}")

finish(failures, "specialization constants, defines and include directories reach the firmware")
