"""docs/configurations.md's generated tables are what spec/gen.py makes of
spec/config_keys.toml and spec/configs.toml today."""
import difflib
import pathlib
import shutil
import subprocess
import sys
import tempfile

root = pathlib.Path(sys.argv[1])
doc = root / "docs" / "configurations.md"
with tempfile.TemporaryDirectory() as tmp:
    tmp = pathlib.Path(tmp)
    shutil.copy(doc, tmp / "configurations.md")
    subprocess.run([sys.executable, root / "spec" / "gen.py", "--spec-dir", root / "spec", "--cpp", tmp / "o.hpp",
                    "--sv", tmp / "o.sv", "--config-doc", tmp / "configurations.md"], check=True)
    want = (tmp / "configurations.md").read_text().splitlines(keepends=True)
have = doc.read_text().splitlines(keepends=True)
diff = list(difflib.unified_diff(have, want, "docs/configurations.md (committed)", "docs/configurations.md (generated)"))
if diff:
    sys.stdout.writelines(diff)
    print("docs/configurations.md is stale: run python3 spec/gen.py --spec-dir spec --cpp /tmp/s.hpp "
          "--sv /tmp/s.sv --config-doc docs/configurations.md")
    sys.exit(1)
print("docs/configurations.md matches spec/")
