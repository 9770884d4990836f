"""A committed generated doc (docs/isa.md, docs/streams.md, the tables of
docs/configurations.md) is what spec/gen.py writes from spec/ today (docs/style.md: CI
regenerates and fails on a diff). The generator gets a copy of the committed doc, so an
option that fills a doc's generated blocks in place (--config-doc) is checked too.

    test_doc_current.py ROOT GEN_OPTION DOC     e.g.  . --isa-doc docs/isa.md
"""
import difflib
import pathlib
import shutil
import subprocess
import sys
import tempfile

root, option, doc = pathlib.Path(sys.argv[1]), sys.argv[2], sys.argv[3]
with tempfile.TemporaryDirectory() as tmp:
    tmp = pathlib.Path(tmp)
    shutil.copy(root / doc, tmp / "doc.md")
    subprocess.run([sys.executable, root / "spec" / "gen.py", "--spec-dir", root / "spec", "--cpp",
                    tmp / "o.hpp", "--sv", tmp / "o.sv", option, tmp / "doc.md"], check=True)
    want = (tmp / "doc.md").read_text().splitlines(keepends=True)
have = (root / doc).read_text().splitlines(keepends=True)
diff = list(difflib.unified_diff(have, want, f"{doc} (committed)", f"{doc} (generated)"))
if diff:
    sys.stdout.writelines(diff)
    print(f"{doc} is stale: run python3 spec/gen.py --spec-dir spec --cpp /tmp/s.hpp "
          f"--sv /tmp/s.sv {option} {doc}")
    sys.exit(1)
print(f"{doc} matches spec/")
