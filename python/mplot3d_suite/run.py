"""Runs matplotlib's own mplot3d tests (from the sdist of the installed
matplotlib, fetched from PyPI into target/mplot3d-suite) with
plytrace.mpl on every 3-D axes, and once without, and lists the tests
whose outcome differs:

    python python/mplot3d_suite/run.py [pytest arguments]

The differences of images are left in target/mplot3d-suite/*/result_images
(each failed comparison as its -expected, -failed-diff and actual PNG).
"""

import json
import shutil
import subprocess
import sys
import tarfile
import urllib.request
from pathlib import Path

import matplotlib

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[1]
WORK = ROOT / "target" / "mplot3d-suite"


def sdist() -> Path:
    """The sdist of the installed matplotlib (downloaded once)."""
    version = matplotlib.__version__
    path = WORK / f"matplotlib-{version}.tar.gz"
    if not path.exists():
        WORK.mkdir(parents=True, exist_ok=True)
        req = urllib.request.Request("https://pypi.org/simple/matplotlib/",
                                     headers={"Accept": "application/vnd.pypi.simple.v1+json"})
        files = json.load(urllib.request.urlopen(req))["files"]
        (url,) = [f["url"] for f in files if f["filename"] == path.name]
        urllib.request.urlretrieve(url, path)
    return path


def tests(how: str) -> Path:
    """The sdist's mplot3d tests with baseline images, and this
    directory's conftest, in a folder of their own."""
    out = WORK / how
    shutil.rmtree(out, ignore_errors=True)
    out.mkdir(parents=True)
    prefix = f"matplotlib-{matplotlib.__version__}/lib/mpl_toolkits/mplot3d/tests/"
    with tarfile.open(sdist()) as tar:
        for m in tar.getmembers():
            if m.name.startswith(prefix) and m.isfile():
                rel = m.name[len(prefix):]
                if rel in ("conftest.py", "__init__.py", "meson.build"):
                    continue
                dest = out / rel
                dest.parent.mkdir(parents=True, exist_ok=True)
                with tar.extractfile(m) as src, open(dest, "wb") as f:
                    shutil.copyfileobj(src, f)
    shutil.copy(HERE / "conftest.py", out / "conftest.py")
    return out


def run(how: str, args) -> dict:
    folder = tests(how)
    report = folder / "report.json"
    env = dict(__import__("os").environ, PLYTRACE_MPL_SUITE=how)
    subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider",
                    "--junit-xml", str(report.with_suffix(".xml")), *args, "."],
                   cwd=folder, env=env, check=False)
    import xml.etree.ElementTree as ET
    outcome = {}
    for case in ET.parse(report.with_suffix(".xml")).iter("testcase"):
        name = f"{case.get('classname')}::{case.get('name')}"
        kind = "passed"
        for child in case:
            if child.tag in ("failure", "error"):
                msg = child.get("message") or ""
                kind = "image" if "images not close" in msg or "ImageComparisonFailure" in msg \
                    else f"{child.tag}: {msg.splitlines()[0][:120] if msg else ''}"
            elif child.tag == "skipped":
                kind = "skipped"
        outcome[name] = kind
    return outcome


def main() -> None:
    args = sys.argv[1:]
    plain, bridged = run("plain", args), run("bridged", args)
    counts = {}
    for name, kind in bridged.items():
        counts[kind.split(":")[0]] = counts.get(kind.split(":")[0], 0) + 1
    print(f"\nmatplotlib {matplotlib.__version__}: {len(bridged)} tests through the bridge:",
          ", ".join(f"{v} {k}" for k, v in sorted(counts.items())))
    for name in sorted(bridged):
        if bridged[name] != plain.get(name):
            print(f"  {name}: {plain.get(name)} -> {bridged[name]}")


if __name__ == "__main__":
    main()
