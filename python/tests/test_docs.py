"""The Python examples of the README and docs/python.md run as written
(in a scratch directory, with a 3-D figure `fig` and its axes `ax` at
hand for the matplotlib ones)."""

import re
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
BLOCKS = [
    (doc, i, code)
    for doc in ("README.md", "docs/python.md")
    for i, code in enumerate(
        re.findall(r"^```python\n(.*?)^```", (ROOT / doc).read_text(), re.S | re.M)
    )
]


def test_the_docs_have_python_examples():
    assert len([b for b in BLOCKS if b[0] == "README.md"]) >= 2


@pytest.mark.parametrize("doc, index, code", BLOCKS, ids=[f"{d}#{i}" for d, i, _ in BLOCKS])
def test_a_documented_example_runs(doc, index, code, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    fig = plt.figure()
    ax = fig.add_subplot(projection="3d")
    x = np.linspace(-1, 1, 10)
    X, Y = np.meshgrid(x, x)
    ax.plot_surface(X, Y, X * Y)
    exec(compile(code, f"{doc} example {index}", "exec"), {"fig": fig, "ax": ax})
    plt.close(fig)
    written = [p for p in tmp_path.iterdir() if p.stat().st_size > 0]
    assert written or "render(" in code
