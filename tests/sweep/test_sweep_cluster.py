"""One sweep three ways, row for row the same: `rpu sweep -j 2`, its GNU parallel job list
(run-parallel.sh) and its Slurm job arrays (slurm/submit.sh) on a single-node Slurm this
test brings up (slurm-wlm and munge from Debian, as root: ../shared/design/TOOLCHAIN.md).
Then a local run killed part-way resumes without redoing the points it finished.

    test_sweep_cluster.py RPU SPEC WORKDIR [--no-slurm]

Only host_seconds may differ between the runs: every other column is a deterministic
measurement. Exit 77 (skipped) when not root or Slurm is not installed, unless
--no-slurm, which leaves Slurm out.
"""
import argparse
import csv
import os
import shutil
import signal
import socket
import subprocess
import sys
import time

ap = argparse.ArgumentParser()
ap.add_argument("rpu")
ap.add_argument("spec")
ap.add_argument("work")
ap.add_argument("--no-slurm", action="store_true")
args = ap.parse_args()
rpu = os.path.abspath(args.rpu)
spec = os.path.abspath(args.spec)
work = os.path.abspath(args.work)
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
failures = []


START = time.time()


def run(cmd, **kw):
    print(f"[{time.time() - START:5.1f} s] {' '.join(cmd)}", flush=True)
    r = subprocess.run(cmd, capture_output=True, text=True, **kw)
    if r.returncode != 0:
        sys.exit(f"FAIL: {' '.join(cmd)} exited {r.returncode}\n{r.stdout}\n{r.stderr}")
    return r


def rows(directory):
    """sweep.csv without host_seconds, keyed by id, in file order."""
    with open(os.path.join(directory, "sweep.csv")) as f:
        table = list(csv.DictReader(f))
    for r in table:
        del r["host_seconds"]
    return table


def compare(name, a, b):
    if [r["id"] for r in a] != [r["id"] for r in b]:
        failures.append(f"{name}: the points differ")
        return
    for x, y in zip(a, b):
        if x != y:
            diff = {k: (x[k], y[k]) for k in x if x[k] != y[k]}
            failures.append(f"{name}: row {x['id']} differs: {diff}")
    print(f"{name}: {len(a)} rows agree")


# 1. Locally, two at a time.
local = os.path.join(work, "local")
run([rpu, "sweep", spec, "-o", local, "-j", "2"])
expected = rows(local)
if len(expected) < 10 or not any(r["leaks"] not in ("", "0") for r in expected):
    failures.append("the sweep measured too little: fewer than 10 rows or no leak anywhere")

# 2. Through GNU parallel: plan, run the job lists, gather.
par = os.path.join(work, "parallel")
run([rpu, "sweep", spec, "-o", par, "--plan"])
if os.path.exists(os.path.join(par, "sweep.csv")):
    failures.append("--plan ran the sweep")
run([os.path.join(par, "run-parallel.sh")], env=dict(os.environ, JOBS="2"))
gathered = run([rpu, "sweep", spec, "-o", par])
if f"{len(expected)} done already; running 0" not in gathered.stderr:
    failures.append(f"gathering after GNU parallel re-ran points: {gathered.stderr}")
compare("GNU parallel vs local", rows(par), expected)

# 3. A killed run resumes: stop it (and the point in flight) after 4 finished points.
resumed = os.path.join(work, "resumed")
proc = subprocess.Popen([rpu, "sweep", spec, "-o", resumed, "-j", "1"], stderr=subprocess.DEVNULL,
                        start_new_session=True)
points = os.path.join(resumed, "points")
deadline = time.time() + 120
while time.time() < deadline:
    finished = [f for f in os.listdir(points) if f.endswith(".json")] if os.path.isdir(points) else []
    if len(finished) >= 4:
        break
    time.sleep(0.05)
os.killpg(proc.pid, signal.SIGTERM)
proc.wait()
kept = {f: os.stat(os.path.join(points, f)).st_mtime_ns for f in os.listdir(points) if f.endswith(".json")}
if len(kept) >= len(expected):
    failures.append("the killed run had finished every point before it was killed")
leftovers = [f for f in os.listdir(points) if f.startswith(".")]
if leftovers:
    failures.append(f"the killed run left temporaries: {leftovers}")
again = run([rpu, "sweep", spec, "-o", resumed, "-j", "2"])
if f"{len(kept)} done already; running {len(expected) - len(kept)}" not in again.stderr:
    failures.append(f"the resumed run did not skip the {len(kept)} finished points: {again.stderr.splitlines()[0]}")
for f, mtime in kept.items():
    if os.stat(os.path.join(points, f)).st_mtime_ns != mtime:
        failures.append(f"the resumed run redid {f}")
print(f"killed after {len(kept)} of {len(expected)} points; the rerun ran the rest")
compare("resumed vs local", rows(resumed), expected)

# 4. Slurm: a single-node cluster, the sweep through two job arrays.
slurm_state = None
if not args.no_slurm:
    if os.geteuid() != 0 or not shutil.which("slurmctld") or not shutil.which("munged"):
        print("SKIP: the Slurm run needs root and slurm-wlm with munge (scripts/setup installs them)")
        sys.exit(77 if not failures else 1)
    slurm_state = os.path.join(work, "slurm-state")
    for d in ("state", "spool", "log"):
        os.makedirs(os.path.join(slurm_state, d))
    host = socket.gethostname().split(".")[0]
    conf = os.path.join(slurm_state, "slurm.conf")
    with open(conf, "w") as f:
        f.write(f"""ClusterName=rpu-test
SlurmctldHost={host}
SlurmUser=root
SlurmctldPort=16817
SlurmdPort=16818
AuthType=auth/munge
StateSaveLocation={slurm_state}/state
SlurmdSpoolDir={slurm_state}/spool
SlurmctldPidFile={slurm_state}/slurmctld.pid
SlurmdPidFile={slurm_state}/slurmd.pid
SlurmctldLogFile={slurm_state}/log/slurmctld.log
SlurmdLogFile={slurm_state}/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
SchedulerType=sched/builtin
SchedulerParameters=sched_min_interval=0
ReturnToService=2
MpiDefault=none
JobCompType=jobcomp/none
AccountingStorageType=accounting_storage/none
NodeName={host} CPUs={os.cpu_count()} State=UNKNOWN
PartitionName=test Nodes={host} Default=YES MaxTime=INFINITE State=UP
""")
    env = dict(os.environ, SLURM_CONF=conf)
    started_munge = False
    if not os.path.exists("/run/munge/munged.pid") or subprocess.run(["munge", "-n"], capture_output=True).returncode:
        os.makedirs("/run/munge", exist_ok=True)
        run(["munged", "--force"])
        started_munge = True
    try:
        run(["slurmctld", "-f", conf], env=env)
        run(["slurmd", "-f", conf], env=env)
        deadline = time.time() + 60
        while time.time() < deadline:
            state = subprocess.run(["sinfo", "-h", "-o", "%t"], capture_output=True, text=True, env=env).stdout.strip()
            if state == "idle":
                break
            time.sleep(0.5)
        else:
            sys.exit(f"FAIL: the Slurm node is not idle after 60 s ({state!r})")
        clu = os.path.join(work, "slurm")
        run([rpu, "sweep", spec, "-o", clu, "--plan"])
        run([os.path.join(clu, "slurm", "submit.sh"), "--wait"], env=env)
        gathered = run([rpu, "sweep", spec, "-o", clu])
        if f"{len(expected)} done already; running 0" not in gathered.stderr:
            failures.append(f"gathering after Slurm re-ran points: {gathered.stderr}")
        compare("Slurm vs local", rows(clu), expected)
    finally:
        # Stop the daemons by their pid files and wait for them to go.
        pids = []
        pid_files = [os.path.join(slurm_state, "slurmd.pid"), os.path.join(slurm_state, "slurmctld.pid")]
        if started_munge:
            pid_files.append("/run/munge/munged.pid")
        for path in pid_files:
            if os.path.exists(path):
                try:
                    pids.append(int(open(path).read()))
                    os.kill(pids[-1], signal.SIGTERM)
                except (ProcessLookupError, ValueError):
                    pass
        deadline = time.time() + 30
        while pids and time.time() < deadline:
            pids = [p for p in pids if os.path.exists(f"/proc/{p}")]
            time.sleep(0.2)
        if pids:
            failures.append(f"the Slurm daemons {pids} did not stop in 30 s")

for f in failures:
    print("FAIL:", f)
sys.exit(1 if failures else 0)
