"""The Python API: arrays in, pictures out; bad input refused with a
clear ValueError; scene files with their errors' places; the GIL
released; Ctrl-C cancelling a render."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import textwrap
import threading
import time
from pathlib import Path

import numpy as np
import pytest

import plytrace

ROOT = Path(__file__).resolve().parents[2]
CCUBE = ROOT / "examples" / "ccube.des"

CUBE_V = np.array(
    [[-1, -1, -1], [1, -1, -1], [1, 1, -1], [-1, 1, -1],
     [-1, -1, 1], [1, -1, 1], [1, 1, 1], [-1, 1, 1]], dtype=float
)
CUBE_F = np.array(
    [[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [2, 3, 7, 6], [1, 2, 6, 5], [0, 4, 7, 3]]
)
CAMERA = plytrace.Camera(eye=(4, -6, 3))


def test_render_gives_height_width_rgb():
    img = plytrace.render(CUBE_V, CUBE_F, size=(64, 48), camera=CAMERA)
    assert img.shape == (48, 64, 3) and img.dtype == np.uint8
    assert tuple(img[0, 0]) == (255, 255, 255), "the corner is the white background"
    assert tuple(img[24, 32]) != (255, 255, 255), "the cube is in the middle"


def test_face_and_vertex_colours():
    red_top = np.tile([0.0, 0.0, 1.0], (6, 1))
    red_top[1] = [1.0, 0.0, 0.0]
    img = plytrace.render(CUBE_V, CUBE_F, colors=red_top, size=(40, 40), camera=CAMERA,
                          material=plytrace.Material(diffuse=0.0))
    top, side = img[12, 20], img[28, 20]
    assert top[0] > 200 and top[0] > 2 * top[2], top
    assert side[2] > 200 and side[2] > 2 * side[0], side
    # Per vertex (8 rows), Gouraud shaded; integers count 0 to 255.
    ramp = (np.linspace(0, 255, 8)[:, None] * [1, 0, 0]).astype(np.uint8)
    img = plytrace.render(CUBE_V, CUBE_F, colors=ramp, size=(40, 40), camera=CAMERA,
                          background=(0, 0, 0)).astype(int)
    assert img[..., 0].sum() > 3 * img[..., 1].sum()
    assert len(np.unique(img[..., 0])) > 20, "shades vary across the faces"
    # As many faces as vertices: the caller must say which.
    tet_v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float)
    tet_f = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    with pytest.raises(ValueError, match="face_colors= or vertex_colors="):
        plytrace.render(tet_v, tet_f, colors=np.eye(4)[:, :3])
    plytrace.render(tet_v, tet_f, face_colors=np.eye(4)[:, :3], size=(16, 16))


def test_a_mirror_reflects():
    """Materials as the scene language has them: a reflective floor
    shows the cube a second time."""
    floor_v = np.array([[-6, -6, -1.01], [6, -6, -1.01], [6, 6, -1.01], [-6, 6, -1.01]], float)
    v = np.concatenate([CUBE_V, floor_v])
    f = [list(r) for r in CUBE_F] + [[8, 9, 10, 11]]
    colors = np.array([[0.9, 0.1, 0.1]] * 6 + [[0.2, 0.2, 0.2]])
    matte = plytrace.render(v, f, face_colors=colors, camera=CAMERA, size=(64, 64))
    mirror = plytrace.render(v, f, face_colors=colors, camera=CAMERA, size=(64, 64),
                             material=plytrace.Material(reflectance=0.8))
    assert (np.abs(matte.astype(int) - mirror).sum(axis=2) > 30).sum() > 50


@pytest.mark.parametrize(
    "vertices, faces, message",
    [
        (np.zeros((4, 2)), [[0, 1, 2]], r"vertices must have shape \(n, 3\), not \(4, 2\)"),
        (np.zeros((2, 3, 3)), [[0, 1, 2]], r"vertices must have shape \(n, 3\)"),
        (np.zeros((0, 3)), [[0, 1, 2]], "vertices is empty"),
        ([[0, 0, 0], [1, np.nan, 0], [0, 1, 0]], [[0, 1, 2]], r"vertex 1 is not finite"),
        ([[0, 0, 0], [1, 0, np.inf], [0, 1, 0]], [[0, 1, 2]], r"vertex 1 is not finite"),
        (CUBE_V, np.zeros((0, 3), dtype=int), "faces is empty"),
        (CUBE_V, [], "faces is empty"),
        (CUBE_V, np.array([[0, 1]]), r"faces must have shape \(m, k\) with k >= 3"),
        (CUBE_V, [[0, 1, 2], [3, 4]], "face 1 has 2 vertices; a face needs 3"),
        (CUBE_V, [[0, 1, 8]], "face 0 names vertex 8, but there are 8 vertices"),
        (CUBE_V, [[0, 1, 2], [0, -1, 2]], "face 1 names vertex -1"),
        (CUBE_V, np.array([[0, 1, 2.5]]), "integer vertex indices"),
    ],
)
def test_bad_arrays_raise_value_error(vertices, faces, message):
    for call in (plytrace.render, plytrace.render_vector):
        with pytest.raises(ValueError, match=message):
            call(vertices, faces)


def test_bad_colours_and_options_raise_value_error():
    with pytest.raises(ValueError, match="colors has 5 rows"):
        plytrace.render(CUBE_V, CUBE_F, colors=np.ones((5, 3)))
    with pytest.raises(ValueError, match="must lie in 0 to 1"):
        plytrace.render(CUBE_V, CUBE_F, face_colors=np.full((6, 3), 2.0))
    with pytest.raises(ValueError, match="not finite"):
        plytrace.render(CUBE_V, CUBE_F, face_colors=np.full((6, 3), np.nan))
    with pytest.raises(ValueError, match=r"face_colors has 5 colours for 6 faces"):
        plytrace.render(CUBE_V, CUBE_F, face_colors=np.ones((5, 3)))
    with pytest.raises(ValueError, match="size must be positive"):
        plytrace.render(CUBE_V, CUBE_F, size=(0, 10))
    with pytest.raises(ValueError, match='format .bmp.: expected "svg", "pdf" or "tex"'):
        plytrace.render_vector(CUBE_V, CUBE_F, format="bmp")
    with pytest.raises(ValueError, match="camera.eye must be three finite numbers"):
        plytrace.render(CUBE_V, CUBE_F, camera=plytrace.Camera(eye=(np.nan, 0, 0)))
    with pytest.raises(ValueError, match="same point"):
        plytrace.render(CUBE_V, CUBE_F, camera=plytrace.Camera(eye=(0, 0, 0)))


def test_vector_formats_and_files(tmp_path):
    svg = plytrace.render_vector(CUBE_V, CUBE_F, camera=CAMERA, size=(100, 80))
    assert svg.startswith(b"<?xml") and b'width="100" height="80"' in svg
    pdf = plytrace.render_vector(CUBE_V, CUBE_F, format="pdf", camera=CAMERA)
    assert pdf.startswith(b"%PDF")
    tex = plytrace.render_vector(CUBE_V, CUBE_F, format="tex", camera=CAMERA)
    assert b"tikzpicture" in tex
    out = tmp_path / "cube.pdf"
    assert plytrace.render_vector(CUBE_V, CUBE_F, path=out, camera=CAMERA) is None
    assert out.read_bytes().startswith(b"%PDF")


def test_scenes_from_files_and_text(tmp_path):
    scene = plytrace.Scene.from_file(CCUBE)
    assert scene.size == (512, 512)
    img = scene.render(size=(48, 48))
    assert img.shape == (48, 48, 3)
    same = plytrace.Scene.from_string(CCUBE.read_text(), CCUBE.parent).render(size=(48, 48))
    assert np.array_equal(img, same)
    assert scene.render_vector().startswith(b"<?xml")
    scene.render_vector(path=tmp_path / "c.tex")
    assert b"tikzpicture" in (tmp_path / "c.tex").read_bytes()
    # Jupyter's pictures.
    assert scene._repr_png_().startswith(b"\x89PNG")
    assert scene._repr_svg_().startswith("<?xml")


def test_scene_errors_carry_their_place(tmp_path):
    with pytest.raises(plytrace.SceneError) as e:
        plytrace.Scene.from_string("lookat 0 0 5  0 0 0 0\nfrobnicate 1 2\n")
    err = e.value
    assert isinstance(err, ValueError)
    assert (err.file, err.line, err.column) == ("<text>", 2, 1)
    assert "unknown command `frobnicate`" in err.message
    assert "<text>:2:1" in str(err) and "^" in str(err)
    bad = tmp_path / "bad.des"
    bad.write_text("color 1 2\n")
    with pytest.raises(plytrace.SceneError) as e:
        plytrace.Scene.from_file(bad)
    assert e.value.file == str(bad) and e.value.line == 1
    with pytest.raises(FileNotFoundError, match="missing.des"):
        plytrace.Scene.from_file(tmp_path / "missing.des")


def _random_triangles(n, seed=1):
    rng = np.random.default_rng(seed)
    c = rng.uniform(-1, 1, (n, 1, 3))
    v = (c + rng.normal(0, 0.25, (n, 3, 3))).reshape(-1, 3)
    return v, np.arange(3 * n).reshape(n, 3)


def test_the_gil_is_released_while_rendering():
    v, f = _random_triangles(2500)
    done = threading.Event()

    def work():
        plytrace.render_vector(v, f, material=plytrace.Material(two_sided=True),
                               shadows=False)
        done.set()

    t = threading.Thread(target=work)
    start = time.perf_counter()
    t.start()
    ticks = 0
    while not done.is_set():
        ticks += 1
        time.sleep(0.001)
    t.join()
    elapsed = time.perf_counter() - start
    assert elapsed > 0.2, f"the render took {elapsed:.2f} s: too short to tell"
    # With the GIL held the main thread would not tick during the render.
    assert ticks > elapsed * 100, (ticks, elapsed)


def test_ctrl_c_cancels_a_render():
    """SIGINT during a render of several seconds raises KeyboardInterrupt
    within a second, and the next render works."""
    script = textwrap.dedent(
        """
        import sys, time, numpy as np, plytrace
        rng = np.random.default_rng(1)
        n = 8000
        c = rng.uniform(-1, 1, (n, 1, 3))
        v = (c + rng.normal(0, 0.25, (n, 3, 3))).reshape(-1, 3)
        f = np.arange(3 * n).reshape(n, 3)
        print("start", flush=True)
        t = time.perf_counter()
        try:
            plytrace.render_vector(v, f, material=plytrace.Material(two_sided=True),
                                   shadows=False)
            print("finished", time.perf_counter() - t, flush=True)
        except KeyboardInterrupt:
            print("interrupted", time.perf_counter() - t, flush=True)
        img = plytrace.render(v[:30], f[:10], size=(16, 16))
        print("after", img.shape, flush=True)
        """
    )
    p = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE, text=True)
    assert p.stdout.readline().strip() == "start"
    time.sleep(1.0)
    sent = time.perf_counter()
    p.send_signal(signal.SIGINT)
    out, _ = p.communicate(timeout=60)
    waited = time.perf_counter() - sent
    assert p.returncode == 0, out
    lines = out.splitlines()
    assert lines[0].startswith("interrupted"), out
    assert waited < 1.5, f"{waited:.2f} s from Ctrl-C to the end: {out}"
    assert lines[1] == "after (16, 16, 3)", out


def test_version():
    assert plytrace.__version__ == "0.1.0"
    assert os.path.exists(plytrace.__file__)
