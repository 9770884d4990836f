"""README.md and docs/*.md link only inside the repository: every relative Markdown link
resolves to a file or folder of the tree, and no text points at ../shared or other
places outside it (docs/style.md "Docs")."""
import pathlib
import re
import sys

root = pathlib.Path(sys.argv[1]).resolve()
bad = []
for page in [root / "README.md", *sorted((root / "docs").glob("*.md"))]:
    text = page.read_text()
    rel = page.relative_to(root)
    for n, line in enumerate(text.splitlines(), 1):
        if "../shared" in line or "shared/design" in line:
            bad.append(f"{rel}:{n}: points outside the repository: {line.strip()}")
    for m in re.finditer(r"\]\(([^)\s]+)\)", text):
        target = m.group(1).split("#")[0]
        if not target or re.match(r"[a-z]+:", target):
            continue
        path = (page.parent / target).resolve()
        n = text[:m.start()].count("\n") + 1
        if root not in path.parents and path != root:
            bad.append(f"{rel}:{n}: link leaves the repository: {m.group(1)}")
        elif not path.exists():
            bad.append(f"{rel}:{n}: link to a missing file: {m.group(1)}")
if bad:
    print("\n".join(bad))
    sys.exit(1)
print("README.md and docs/ link only inside the repository")
