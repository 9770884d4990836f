"""The end of the check scripts here: each failure on its line, else what held; the status."""
import sys


def finish(failures, held):
    for f in failures:
        print(f"FAIL: {f}")
    if not failures:
        print(f"ok: {held}")
    sys.exit(1 if failures else 0)
