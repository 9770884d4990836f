#!/usr/bin/env python3
"""The GLSL compile cache runs only what was compiled for the key an entry is stored
under (docs/shaders.md): an entry replaced by another valid entry, or by a firmware
file, is compiled again, and the image is the shaders' own.

    compile_cache.py RPU GLSL_DIR WORKDIR
"""
import os
import shutil
import subprocess
import sys

from outcome import finish

rpu, glsl, work = sys.argv[1], sys.argv[2], sys.argv[3]
shutil.rmtree(work, ignore_errors=True)
cache = os.path.join(work, "cache")
os.makedirs(cache)
env = dict(os.environ, RPU_CACHE_DIR=cache)
failures = []

# Two shader sets for the Cornell box's `whitted` shader: the library's, and phong.rchit
# under the name whitted.rchit.
a_dir, b_dir = os.path.join(work, "a"), os.path.join(work, "b")
shutil.copytree(glsl, a_dir)
shutil.copytree(glsl, b_dir)
shutil.copy(os.path.join(glsl, "phong.rchit"), os.path.join(b_dir, "whitted.rchit"))


def render(shaders, name):
    out = os.path.join(work, name + ".png")
    files = [os.path.join(shaders, f) for f in ("whitted.rgen", "whitted.rchit", "background.rmiss")]
    r = subprocess.run([rpu, "render", "cornell", "--backend", "functional", "--width", "16", "--height", "12",
                        "--spp", "1", "--firmware", *files, "-o", out], capture_output=True, text=True, env=env)
    if r.returncode != 0:
        failures.append(f"{name}: status {r.returncode}: {r.stderr[-300:]}")
    with open(out, "rb") as f:
        return f.read()


def entries():
    return set(os.listdir(cache))


a_image = render(a_dir, "a")
(a_entry,) = entries()
b_image = render(b_dir, "b")
(b_entry,) = entries() - {a_entry}
if a_image == b_image:
    failures.append("the two shader sets render the same image: the test cannot tell them apart")

# Another valid entry in A's place.
shutil.copy(os.path.join(cache, b_entry), os.path.join(cache, a_entry))
if render(a_dir, "a_after_b") != a_image:
    failures.append("with B's entry in A's place, A's render ran B's firmware")

# A firmware file in A's place.
fw = os.path.join(work, "b.rfw")
subprocess.run([rpu, "cc", *[os.path.join(b_dir, f) for f in ("whitted.rgen", "whitted.rchit", "background.rmiss")],
                "-o", fw], check=True, capture_output=True)
shutil.copy(fw, os.path.join(cache, a_entry))
if render(a_dir, "a_after_rfw") != a_image:
    failures.append("with a firmware file in A's entry, A's render ran it")

finish(failures, "a replaced compile-cache entry is compiled again")
