"""scripts/bench-record's conversions on inputs written here: a callgrind profile split
into the rays traced and the instructions by function, and a results file appended to
without touching its old lines; and every measurement writes a file that a table of
scripts/doc-tables reads."""
import json
import pathlib
import re
import sys
import tempfile
from importlib.machinery import SourceFileLoader

sys.dont_write_bytecode = True
root = pathlib.Path(sys.argv[1])
record = SourceFileLoader("bench_record", str(root / "scripts" / "bench-record")).load_module()
tables = SourceFileLoader("doc_tables", str(root / "scripts" / "doc-tables")).load_module()

# Three calls from main into trace_with (inclusive 300 + 5 instructions); inside it 200 of
# its own, setup_ray (60) and memcpy (40), named once and then by number.
PROFILE = """# callgrind format
version: 1
positions: line
events: Ir

fn=(1) main
cfn=(2) rpu::functional::TraceHit rpu::functional::Tracer::trace_with<A, B>(A const&) const [clone .constprop.0]
calls=2 0
0 200
cfn=(2)
calls=1 0
0 105

fn=(2)
0 150
cfn=(3) bool rpu::functional::setup_ray<rpu::functional::Fast32Arith>(A const&, bool)
calls=3 0
0 60
0 50
cfn=(4) __memcpy_avx_unaligned_erms
calls=9 0
0 40

fn=(3)
0 60
"""
with tempfile.TemporaryDirectory() as tmp:
    tmp = pathlib.Path(tmp)
    (tmp / "cg.out").write_text(PROFILE)
    calls, inclusive, own = record.callgrind_calls(tmp / "cg.out", re.compile(r"::trace_with<"))
    want = (3, 305, {"Tracer::trace_with": 200, "setup_ray": 60, "__memcpy_avx_unaligned_erms": 40})
    if (calls, inclusive, own) != want:
        sys.exit(f"callgrind_calls: got {(calls, inclusive, own)}, want {want}")

    results = tmp / "kind.json"
    old = '{\n "description": "d",\n "records": [\n  {"commit": "a", "x": 1}\n ]\n}\n'
    results.write_text(old)
    record.append(results, [{"commit": "b", "x": 2}, {"commit": "c", "x": 3}])
    text = results.read_text()
    kept = text.startswith(old[:old.index(" ]")].rstrip())
    if not kept or [r["x"] for r in json.loads(text)["records"]] != [1, 2, 3]:
        sys.exit(f"append changed the old lines or lost a record:\n{text}")

read = {spec["file"] for spec in tables.TABLES.values()}
for m in record.MEASUREMENTS.values():
    if m.file not in read:
        sys.exit(f"bench-record {m.name} writes bench/results/{m.file}, which no table of scripts/doc-tables reads")
    if not (root / "bench" / "results" / m.file).exists():
        sys.exit(f"bench-record {m.name}: bench/results/{m.file} does not exist")
print(f"callgrind split, append and {len(record.MEASUREMENTS)} measurements' files check out")
