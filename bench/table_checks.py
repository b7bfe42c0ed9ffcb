"""What the tests of bench's summarisers share: a list of failed checks, a summariser run
on a runs file, and the row of a markdown table.
"""
import os
import subprocess
import sys
import tempfile

failures = []


def check(what, ok):
    if not ok:
        failures.append(what)


def run(script, text):
    """The summariser SCRIPT on a runs file holding TEXT: (the finished process, the file's name)."""
    with tempfile.NamedTemporaryFile("w", suffix=".txt", delete=False) as f:
        f.write(text)
    try:
        return subprocess.run([sys.executable, script, f.name], capture_output=True, text=True), f.name
    finally:
        os.unlink(f.name)


def table_row(out, *key):
    """The cells of the first table row of OUT that starts with the cells KEY, or None."""
    for line in out.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if cells[:len(key)] == [str(k) for k in key]:
            return cells
    return None
