"""Shared fixtures: the tests' own directory on the import path, and a
table of the bridge's scores printed at the end of the run."""

import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).parent))

_RESULTS = []


@pytest.fixture
def results():
    return _RESULTS


def pytest_terminal_summary(terminalreporter):
    if not _RESULTS:
        return
    tr = terminalreporter
    tr.section("wrong surface, % of interior pixels (line: % of line samples)")
    for name, fmt, how, s in sorted(_RESULTS, key=lambda r: (r[0], r[2], r[1])):
        parts = [f"surface {s['surface'].percent:6.2f}% of {s['surface'].pixels}"]
        if "line" in s:
            parts.append(f"line {s['line'].percent:6.2f}% of {s['line'].pixels}")
        tr.write_line(f"{name:14} {fmt:4} {how:10} " + ", ".join(parts))
