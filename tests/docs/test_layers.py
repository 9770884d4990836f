"""The C++ model's layers as docs/architecture.md "Layers" draws them, checked on the
includes: the command line reaches the device layer only through the registry, only the
registry includes a header of sim/ (the rtl backend), the device interface and the
functional backend include nothing of the cycle backend, and no backend includes the
registry or the command line."""
import pathlib
import re
import sys

root = pathlib.Path(sys.argv[1]).resolve()
sim_headers = {p.name for p in (root / "sim").glob("*.hpp")}
registry = {"cmodel/device/registry.hpp", "cmodel/device/registry.cpp"}


def rule_broken(path, header):
    """Why `path` (relative to the root) may not include `header`, or None."""
    if header in sim_headers and path not in registry:
        return "a header of sim/ outside sim/ and the registry"
    if path.startswith("cmodel/cli/") and re.match(r"(device|cycle)/", header) and header != "device/registry.hpp":
        return "the command line includes the device layer only through device/registry.hpp"
    if path.startswith("cmodel/device/") and path not in registry and header.startswith("cycle/"):
        return "the device interface and the functional backend lie below the cycle backend"
    if path.startswith(("cmodel/device/", "cmodel/cycle/")) and path not in registry and (
            header == "device/registry.hpp" or header.startswith("cli/")):
        return "a backend knows neither the registry nor the command line"
    return None


bad = []
for source in sorted((root / "cmodel").rglob("*")):
    if source.suffix not in (".cpp", ".hpp"):
        continue
    path = source.relative_to(root).as_posix()
    for n, line in enumerate(source.read_text().splitlines(), 1):
        m = re.match(r'\s*#\s*include\s+"([^"]+)"', line)
        if m and (why := rule_broken(path, m.group(1))):
            bad.append(f"{path}:{n}: includes {m.group(1)}: {why} (docs/architecture.md \"Layers\")")
if bad:
    print("\n".join(bad))
    sys.exit(1)
print("the includes keep to docs/architecture.md's layers")
