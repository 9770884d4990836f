"""Outputs interrupted by SIGINT, and a real full disk: the old file keeps its bytes and
no temporary is left beside it (issue 14 class 3).

    interrupted_outputs.py RPU WORKDIR SWEEP_FILE

1. SIGINT while a cycle render streams its --trace (the temporary lives the whole frame).
2. SIGINT while a large EXR is being written.
3. As root: a 64 KiB tmpfs that an EXR does not fit on, and a 256 KiB one that a sweep
   fills (its failed points must name the full disk). Skipped, saying so, otherwise.
"""
import os
import shutil
import signal
import subprocess
import sys
import time

rpu, work, sweep_file = sys.argv[1], sys.argv[2], sys.argv[3]
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
OLD = b"the previous file\n"
failures = []


def old_file(name, directory=work):
    path = os.path.join(directory, name)
    with open(path, "wb") as f:
        f.write(OLD)
    return path


def temporaries(path):
    directory, name = os.path.split(path)
    return [f for f in os.listdir(directory) if f.startswith(f".{name}.")]


def check_kept(case, path):
    with open(path, "rb") as f:
        if f.read() != OLD:
            failures.append(f"{case}: {path} changed")
    if temporaries(path):
        failures.append(f"{case}: temporaries left beside {path}: {temporaries(path)}")


def interrupt_when_written(case, command, path, min_bytes):
    """Starts `command`, sends SIGINT once the temporary of `path` holds min_bytes."""
    p = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    deadline = time.monotonic() + 120
    seen = 0
    while p.poll() is None and time.monotonic() < deadline:
        for t in temporaries(path):
            try:
                seen = max(seen, os.path.getsize(os.path.join(os.path.dirname(path), t)))
            except OSError:
                pass
        if seen >= min_bytes:
            p.send_signal(signal.SIGINT)
            break
        time.sleep(0.001)
    _, err = p.communicate(timeout=120)
    print(f"{case}: temporary reached {seen} bytes; status {p.returncode}\n{err.decode()}")
    if seen < min_bytes:
        failures.append(f"{case}: never saw a temporary of {min_bytes} bytes beside {path}")
    elif p.returncode != -signal.SIGINT:
        failures.append(f"{case}: status {p.returncode}, expected death by SIGINT ({-signal.SIGINT})")
    check_kept(case, path)


trace = old_file("trace.json")
interrupt_when_written("SIGINT during --trace",
                       [rpu, "render", "cornell", "--backend", "cycle", "--width", "128", "--height", "128",
                        "--spp", "1", "--trace", trace, "--trace-window", "0", "100000000",
                        "-o", os.path.join(work, "never.png")], trace, 1 << 20)

exr = old_file("big.exr")
interrupt_when_written("SIGINT during an EXR write",
                       [rpu, "render", "tetra:1", "--width", "4096", "--height", "4096", "--spp", "1",
                        "--max-depth", "0", "-o", exr], exr, 1)

if os.geteuid() != 0:
    print("SKIP full tmpfs: needs root to mount one (the RLIMIT_FSIZE tests in tests/cli always run)")
else:
    mnt = os.path.join(work, "tmpfs")
    os.makedirs(mnt)
    subprocess.run(["mount", "-t", "tmpfs", "-o", "size=64k", "tmpfs", mnt], check=True)
    try:
        full = old_file("full.exr", mnt)
        r = subprocess.run([rpu, "render", "cornell", "--width", "256", "--height", "256", "--spp", "1", "-o", full],
                           capture_output=True, text=True, timeout=120)
        print(f"full tmpfs: status {r.returncode}\n{r.stderr}")
        expected = f"rpu: error: {full}: cannot write the file: "
        if r.returncode != 1 or expected not in r.stderr or "the previous file is unchanged" not in r.stderr:
            failures.append(f"full tmpfs: status {r.returncode}, expected 1 and '{expected}...'")
        check_kept("full tmpfs", full)
    finally:
        subprocess.run(["umount", mnt], check=True)
    # A sweep that fills its file system: the failed points say so, though their logs
    # are empty.
    subprocess.run(["mount", "-t", "tmpfs", "-o", "size=256k", "tmpfs", mnt], check=True)
    try:
        r = subprocess.run([rpu, "sweep", sweep_file, "-o", os.path.join(mnt, "sweep")], capture_output=True, text=True,
                           timeout=600)
        print(f"sweep on a full tmpfs: status {r.returncode}\n{r.stderr[-2000:]}")
        if r.returncode != 1 or "FAILED" not in r.stderr or "No space left on device" not in r.stderr:
            failures.append(f"sweep on a full tmpfs: status {r.returncode}, expected 1 and a FAILED point that names "
                            "'No space left on device'")
    finally:
        subprocess.run(["umount", mnt], check=True)

for f in failures:
    print(f"FAIL: {f}")
sys.exit(1 if failures else 0)
