"""docs/isa.md is what spec/gen.py writes from spec/isa.toml today (docs/style.md "One source": CI
regenerates and fails on a diff)."""
import difflib
import pathlib
import subprocess
import sys
import tempfile

root = pathlib.Path(sys.argv[1])
with tempfile.TemporaryDirectory() as tmp:
    tmp = pathlib.Path(tmp)
    subprocess.run([sys.executable, root / "spec" / "gen.py", "--spec-dir", root / "spec", "--cpp",
                    tmp / "o.hpp", "--sv", tmp / "o.sv", "--isa-doc", tmp / "isa.md"], check=True)
    want = (tmp / "isa.md").read_text().splitlines(keepends=True)
have = (root / "docs" / "isa.md").read_text().splitlines(keepends=True)
diff = list(difflib.unified_diff(have, want, "docs/isa.md (committed)", "docs/isa.md (generated)"))
if diff:
    sys.stdout.writelines(diff)
    print("docs/isa.md is stale: run python3 spec/gen.py --spec-dir spec --cpp /tmp/s.hpp "
          "--sv /tmp/s.sv --isa-doc docs/isa.md")
    sys.exit(1)
print("docs/isa.md matches spec/isa.toml")
