"""A co-simulation harness's --trace waveforms on bad paths and full disks (issue 14
class 3): checked before the run, written whole or not at all, never a SIGBUS.

    trace_outputs.py WORKDIR [--small-waves] -- HARNESS ARGS...

Runs HARNESS ARGS --trace FILE with FILE in a missing directory, under a file-size limit
(RLIMIT_FSIZE, always), on a 64 KiB tmpfs and with a full /tmp, where the FST writer
maps its scratch files (root only; skipped, saying so, otherwise), then once where it
fits. The failures must exit with status 2 and say which file could
not be written, leave the old file's bytes and no temporary beside it. With
--small-waves (a small design, whose writer's scratch fits a 16 KiB /tmp), the full
/tmp case may also succeed, with the whole file written.
"""
import os
import resource
import shutil
import subprocess
import sys

work = sys.argv[1]
args = sys.argv[2:]
small_waves = args[0] == "--small-waves"
if small_waves:
    args = args[1:]
command = args[1:] if args[0] == "--" else args
name = os.path.basename(command[0])
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
OLD = b"the previous waves\n"
failures = []


def run(case, trace, limit=None, wrap=()):
    def limit_file_size():
        resource.setrlimit(resource.RLIMIT_FSIZE, (limit, resource.RLIM_INFINITY))

    r = subprocess.run(list(wrap) + command + ["--trace", trace], capture_output=True, text=True, timeout=300,
                       preexec_fn=limit_file_size if limit else None)
    print(f"{case}: status {r.returncode}\n{r.stderr}")
    return r


def expect_failure(case, r, trace, message):
    if r.returncode != 2:
        failures.append(f"{case}: status {r.returncode}, expected 2")
    if f"{name}: {trace}: {message}" not in r.stderr:
        failures.append(f"{case}: stderr does not say '{trace}: {message}'")


def expect_no_temporaries(case, trace):
    directory, base = os.path.split(trace)
    left = [f for f in os.listdir(directory) if f.startswith(f".{base}.")]
    if left:
        failures.append(f"{case}: temporaries left beside {trace}: {left}")


def expect_kept(case, trace):
    with open(trace, "rb") as f:
        if f.read() != OLD:
            failures.append(f"{case}: {trace} changed")
    expect_no_temporaries(case, trace)


def old_file(path):
    with open(path, "wb") as f:
        f.write(OLD)
    return path


missing = os.path.join(work, "no_such_dir", "waves.fst")
expect_failure("missing directory", run("missing directory", missing), missing,
               f"the directory '{os.path.dirname(missing)}' does not exist")

limited = old_file(os.path.join(work, "limited.fst"))
r = run("file-size limit", limited, limit=64 << 10)
expect_failure("file-size limit", r, limited, "cannot write the file: ")
expect_kept("file-size limit", limited)

if os.geteuid() != 0:
    print("SKIP full tmpfs: needs root to mount one (the RLIMIT_FSIZE case always runs)")
else:
    mnt = os.path.join(work, "tmpfs")
    os.makedirs(mnt)
    subprocess.run(["mount", "-t", "tmpfs", "-o", "size=64k", "tmpfs", mnt], check=True)
    try:
        full = old_file(os.path.join(mnt, "full.fst"))
        r = run("full tmpfs", full)
        expect_failure("full tmpfs", r, full, "cannot write the file: ")
        expect_kept("full tmpfs", full)
    finally:
        subprocess.run(["umount", mnt], check=True)
    # The FST writer maps its scratch files, which tmpfile() puts in /tmp: a full /tmp
    # made the harness die of SIGBUS with a half file. A private 16 KiB /tmp.
    if os.path.realpath(work).startswith("/tmp/"):
        print(f"SKIP full /tmp: {work} is under /tmp, which the case hides")
    else:
        small_tmp = ["unshare", "-m", "sh", "-c", 'mount -t tmpfs -o size=16k tmpfs /tmp && exec "$@"', "sh"]
        bus = old_file(os.path.join(work, "bus.fst"))
        r = run("full /tmp", bus, wrap=small_tmp)
        if small_waves and r.returncode == 0:
            with open(bus, "rb") as f:
                if f.read() == OLD:
                    failures.append(f"full /tmp: status 0 but {bus} was not replaced")
            expect_no_temporaries("full /tmp", bus)
        else:
            expect_failure("full /tmp", r, bus, "cannot write the file: bus error in a memory-mapped write")
            expect_kept("full /tmp", bus)

good = old_file(os.path.join(work, "good.fst"))
r = run("fits", good)
if r.returncode != 0:
    failures.append(f"fits: status {r.returncode}, expected 0")
with open(good, "rb") as f:
    if f.read() == OLD:
        failures.append(f"fits: {good} was not replaced")
expect_no_temporaries("fits", good)

for f in failures:
    print(f"FAIL: {f}")
sys.exit(1 if failures else 0)
