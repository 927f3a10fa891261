"""Hostile input to the Python API: every bad argument is a Python
exception (ValueError, TypeError, OSError, MemoryError) that names it;
never a crash, a PanicException, a bare OverflowError, a half-written
file or a file written over an input. Numeric input of any sensible
dtype and memory layout gives the same picture."""

from __future__ import annotations

import concurrent.futures
import shutil
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import numpy as np
import pytest

import plytrace
from plytrace import _native

ROOT = Path(__file__).resolve().parents[2]
CCUBE = ROOT / "examples" / "ccube.des"
CUBE_DET = ROOT / "examples" / "det" / "cube.det"

CUBE_V = np.array(
    [[-1, -1, -1], [1, -1, -1], [1, 1, -1], [-1, 1, -1],
     [-1, -1, 1], [1, -1, 1], [1, 1, 1], [-1, 1, 1]], dtype=float
)
CUBE_F = np.array(
    [[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [2, 3, 7, 6], [1, 2, 6, 5], [0, 4, 7, 3]]
)
CAMERA = plytrace.Camera(eye=(4, -6, 3))
SMALL = (24, 24)


def _cube(**kw):
    kw.setdefault("camera", CAMERA)
    kw.setdefault("size", SMALL)
    v = kw.pop("vertices", CUBE_V)
    f = kw.pop("faces", CUBE_F)
    return plytrace.render(v, f, **kw)


def _run(script: str, *args: str, timeout: float = 120) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-c", textwrap.dedent(script), *args],
        capture_output=True, text=True, timeout=timeout,
    )


# Files: written whole or not at all, never over an input.

FULL_DISK = """
    import resource, signal, sys
    from pathlib import Path
    import numpy as np
    out = Path(sys.argv[1])
    out.write_bytes(b"the earlier file")
    # Writes past 256 bytes fail with EFBIG, as on a full disk.
    signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
    resource.setrlimit(resource.RLIMIT_FSIZE, (256, resource.RLIM_INFINITY))
    rng = np.random.default_rng(1)
    v = rng.uniform(-1, 1, (300, 3))
    f = np.arange(300).reshape(100, 3)
    try:
        {write}
    except OSError as e:
        print("OSError", e)
    else:
        print("written")
"""

WRITERS = {
    "render_vector": "import plytrace; plytrace.render_vector(v, f, path=out, "
                     "material=plytrace.Material(two_sided=True))",
    "Scene.render_vector": "import plytrace; plytrace.Scene.from_string("
                           "'resolution 64 64\\nlookat 0 0 6 0 0 0 0\\ndefobj cube\\nendobj\\n', "
                           f"{str(ROOT / 'examples')!r}).render_vector(path=out)",
    "mpl.savefig": "import matplotlib; matplotlib.use('Agg'); import matplotlib.pyplot as plt; "
                   "import plytrace.mpl; fig = plt.figure(); ax = fig.add_subplot(projection='3d'); "
                   "X, Y = np.meshgrid(np.arange(20.), np.arange(20.)); ax.plot_surface(X, Y, X * Y); "
                   "plytrace.mpl.savefig(fig, out)",
}


@pytest.mark.parametrize("writer", sorted(WRITERS))
def test_a_full_disk_keeps_the_earlier_file(writer, tmp_path):
    """A write that fails part way (EFBIG under RLIMIT_FSIZE, as ENOSPC on
    a full disk) raises OSError and leaves the earlier file whole, with no
    temporary file beside it."""
    out = tmp_path / ("picture.svg" if writer != "Scene.render_vector" else "scene.svg")
    r = _run(FULL_DISK.replace("{write}", WRITERS[writer]), str(out))
    assert r.returncode == 0, r.stderr
    assert r.stdout.startswith("OSError"), r.stdout + r.stderr
    assert out.read_bytes() == b"the earlier file"
    assert sorted(p.name for p in tmp_path.iterdir()) == [out.name]


def test_files_are_written_whole(tmp_path):
    out = tmp_path / "cube.svg"
    out.write_bytes(b"old")
    assert plytrace.render_vector(CUBE_V, CUBE_F, path=out, camera=CAMERA) is None
    assert out.read_bytes().startswith(b"<?xml")
    assert [p.name for p in tmp_path.iterdir()] == ["cube.svg"]


def test_path_over_an_input_is_refused(tmp_path):
    """As the program's outputs: a scene file read, or an object file it
    read, is never written over (by any name for it)."""
    shutil.copytree(CCUBE.parent / "det", tmp_path / "det")
    scene_file = tmp_path / "ccube.des"
    shutil.copy(CCUBE, scene_file)
    scene = plytrace.Scene.from_file(scene_file)
    before = {p: p.read_bytes() for p in (scene_file, tmp_path / "det" / "cube.det")}
    for target in (scene_file, tmp_path / "det" / "cube.det", tmp_path / "det" / ".." / "ccube.des"):
        with pytest.raises(ValueError, match="an input"):
            scene.render_vector("svg", path=target)
        with pytest.raises(ValueError, match="an input"):
            plytrace.render_vector(CUBE_V, CUBE_F, format="svg", path=target)
    assert {p: p.read_bytes() for p in before} == before
    scene.render_vector(path=tmp_path / "ccube.svg")
    assert (tmp_path / "ccube.svg").read_bytes().startswith(b"<?xml")


@pytest.mark.parametrize("path, error", [(5, TypeError), ("", ValueError), (None, None)])
def test_bad_paths(path, error, tmp_path):
    if error is None:
        assert plytrace.render_vector(CUBE_V, CUBE_F, path=path, camera=CAMERA) is not None
        return
    with pytest.raises(error, match="path"):
        plytrace.render_vector(CUBE_V, CUBE_F, format="svg", path=path)


def test_a_directory_or_a_missing_folder_is_an_os_error(tmp_path):
    with pytest.raises(OSError):
        plytrace.render_vector(CUBE_V, CUBE_F, format="svg", path=tmp_path)
    with pytest.raises(OSError):
        plytrace.render_vector(CUBE_V, CUBE_F, path=tmp_path / "no" / "such.svg")
    assert [p.name for p in tmp_path.iterdir()] == []


# Numbers that are not finite, anywhere.

NAN_INF = [np.nan, np.inf, -np.inf]


@pytest.mark.parametrize("value", NAN_INF)
@pytest.mark.parametrize(
    "field",
    ["diffuse", "specular", "shininess", "reflectance", "transmittance", "index", "transparency"],
)
def test_material_refuses_what_is_not_finite(field, value):
    with pytest.raises(ValueError, match=f"material.{field}"):
        _cube(material=plytrace.Material(**{field: value}))


@pytest.mark.parametrize(
    "field, value",
    [("diffuse", 1.5), ("specular", -0.1), ("shininess", -1), ("index", 0),
     ("transparency", 2), ("reflectance", -1), ("transmittance", 1.01)],
)
def test_material_refuses_what_the_scene_language_refuses(field, value):
    with pytest.raises(ValueError, match=f"material.{field}"):
        _cube(material=plytrace.Material(**{field: value}))


@pytest.mark.parametrize("value", ["0.5", None, 1j, True])
def test_material_refuses_what_is_not_a_number(value):
    with pytest.raises(TypeError, match="material.diffuse"):
        _cube(material=plytrace.Material(diffuse=value))


@pytest.mark.parametrize("value", NAN_INF)
@pytest.mark.parametrize("field", ["position", "color", "range"])
def test_light_refuses_what_is_not_finite(field, value):
    light = dict(position=(1.0, -5.0, 3.0), color=(1.0, 1.0, 1.0), range=100.0)
    light[field] = value if field == "range" else (1.0, value, 1.0)
    with pytest.raises(ValueError, match=rf"lights\[1\].{field}"):
        _cube(lights=[plytrace.Light((0, -5, 0)), plytrace.Light(**light)])


def test_light_refuses_negative_colours_and_ranges():
    with pytest.raises(ValueError, match=r"lights\[0\].range"):
        _cube(lights=[plytrace.Light((0, -5, 0), range=0)])
    with pytest.raises(ValueError, match=r"lights\[0\].color"):
        _cube(lights=[plytrace.Light((0, -5, 0), color=(1, -1, 1))])
    # Brighter than 1 is allowed, as in the scene language.
    _cube(lights=[plytrace.Light((0, -5, 0), color=(2, 2, 2))])
    with pytest.raises(TypeError, match="lights"):
        _cube(lights=plytrace.Light((0, -5, 0)))


@pytest.mark.parametrize("value", NAN_INF)
@pytest.mark.parametrize("field", ["eye", "target", "up", "fovy", "near", "far", "ortho"])
def test_camera_refuses_what_is_not_finite(field, value):
    cam = dict(eye=(4.0, -6.0, 3.0))
    if field in ("eye", "target", "up"):
        cam[field] = (0.5, value, 0.5)
    elif field == "ortho":
        cam[field] = (-1, 1, value, 1)
    else:
        cam[field] = value
    with pytest.raises(ValueError, match=f"camera.{field}"):
        _cube(camera=plytrace.Camera(**cam))


@pytest.mark.parametrize("value", NAN_INF)
def test_colours_refuse_what_is_not_finite(value):
    for kw in ("background", "colors"):
        with pytest.raises(ValueError, match=kw):
            _cube(**{kw: (1.0, value, 0.0)})
    with pytest.raises(ValueError, match="material.color"):
        _cube(material=plytrace.Material(color=(value, 0, 0)))
    with pytest.raises(ValueError, match="face_colors"):
        _cube(face_colors=np.full((6, 3), value))
    with pytest.raises(ValueError, match="vertex 2 is not finite"):
        v = CUBE_V.copy()
        v[2, 1] = value
        _cube(vertices=v)


def test_the_native_layer_refuses_what_is_not_finite():
    """The library checks again what the Python layer checked (for a
    caller of ``plytrace._native``): no NaN reaches the renderer."""
    s = _native.NativeScene.new((4, -6, 3), (0, 0, 0), (0, 0, 1), 45, 0.1, 100, None, 8, 8)
    with pytest.raises(ValueError, match="light range"):
        s.add_light((0, 0, 5), (1, 1, 1), float("nan"), True)
    with pytest.raises(ValueError, match="light position"):
        s.add_light((0, float("inf"), 5), (1, 1, 1), 10, True)
    with pytest.raises(ValueError, match="background"):
        s.set_background((0, float("nan"), 0))
    with pytest.raises(ValueError, match="ambient"):
        s.set_ambient((2, 0, 0))
    args = (CUBE_V, CUBE_F.reshape(-1).astype(np.uint32), np.full(6, 4, dtype=np.uint32),
            None, None, (1, 1, 1))
    with pytest.raises(ValueError, match="material shininess"):
        s.add_mesh("m", *args, [0.6, 0, float("nan"), 0, 0, 1, 0], False, False)
    with pytest.raises(ValueError, match="material index"):
        s.add_mesh("m", *args, [0.6, 0, 0, 0, 0, float("inf"), 0], False, False)
    with pytest.raises(ValueError, match="do not add up"):
        s.add_mesh("m", CUBE_V, args[1], np.full(5, 4, dtype=np.uint32), None, None, (1, 1, 1),
                   [0.6, 0, 0, 0, 0, 1, 0], False, False)
    with pytest.raises(ValueError, match="each side must be 1 to 65536"):
        s.render((70000, 1), True, True)


# Sizes.

BAD_SIZES = [
    ((0, 5), ValueError), ((-1, 5), ValueError), ((10**9, 10**9), ValueError),
    ((2**32, 1), ValueError), ((2**64, 1), ValueError), ((65537, 1), ValueError),
    ((20000, 20000), ValueError),
    ((1.5, 2), TypeError), ((np.nan, 3), TypeError), ((np.inf, 3), TypeError),
    ("ab", TypeError), ((16,), TypeError), (16, TypeError), ((True, 16), TypeError),
    ((16, "16"), TypeError),
]


@pytest.mark.parametrize("size, error", BAD_SIZES, ids=[repr(s) for s, _ in BAD_SIZES])
def test_absurd_sizes_raise_an_error_naming_size(size, error):
    scene = plytrace.Scene.from_file(CCUBE)
    calls = [
        lambda: _cube(size=size),
        lambda: plytrace.render_vector(CUBE_V, CUBE_F, size=size),
        lambda: scene.render(size=size),
        lambda: scene.render_vector(size=size),
    ]
    for call in calls:
        with pytest.raises(error, match="size"):
            call()


def test_numpy_integer_sizes_are_sizes():
    assert _cube(size=(np.int64(20), np.uint8(10))).shape == (10, 20, 3)


def test_a_frame_over_the_budget_is_a_memory_error_naming_the_budget():
    big = plytrace.Budgets(frame_memory=1)
    with pytest.raises(MemoryError, match=r"budgets=plytrace.Budgets\(frame_memory=N\)"):
        _cube(size=(1024, 1024), budgets=big)
    with pytest.raises(MemoryError, match=r"Budgets\(pixels=N\)"):
        plytrace.Scene.from_file(CCUBE).render(size=(64, 64), budgets=plytrace.Budgets(pixels=100))
    # Raised, it passes.
    assert _cube(size=(600, 600), budgets=plytrace.Budgets(frame_memory=2)).shape == (600, 600, 3)


def test_budgets_are_checked():
    with pytest.raises(ValueError, match="budgets.polygons"):
        _cube(budgets=plytrace.Budgets(polygons=-1))
    with pytest.raises(TypeError, match="budgets.rays"):
        _cube(budgets=plytrace.Budgets(rays=1.5))
    with pytest.raises(TypeError, match="budgets must be a plytrace.Budgets"):
        _cube(budgets={"polygons": 5})
    assert plytrace.Budgets().polygons == 4_000_000


# Polygon budgets: refused before the arrays are copied.

MANY_FACES = """
    import resource, numpy as np, plytrace
    n = 10**7
    v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], float)
    # 10^7 faces without 10^7 faces' memory: a broadcast view.
    f = np.broadcast_to(np.array([0, 1, 2]), (n, 3))
    before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    try:
        plytrace.render(v, f, size=(8, 8))
        print("rendered")
    except MemoryError as e:
        print("MemoryError", e)
    grown = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - before
    print("grown KiB", grown)
"""


def test_ten_million_faces_are_refused_before_they_are_copied():
    r = _run(MANY_FACES, timeout=300)
    assert r.returncode == 0, r.stderr
    lines = r.stdout.splitlines()
    assert lines[0].startswith("MemoryError"), r.stdout + r.stderr
    assert "10000000" in lines[0] and "budgets=plytrace.Budgets(polygons=N)" in lines[0]
    grown_kib = int(lines[1].split()[-1])
    assert grown_kib < 100 * 1024, f"{grown_kib} KiB taken to refuse"


def test_polygon_budget_applies_to_every_form_of_faces():
    tight = plytrace.Budgets(polygons=5)
    for faces in (CUBE_F, [list(f) for f in CUBE_F], CUBE_F.astype(float)):
        with pytest.raises(MemoryError, match=r"6 faces.*Budgets\(polygons=N\)"):
            _cube(faces=faces, budgets=tight)
    with pytest.raises(MemoryError, match=r"Budgets\(model_memory=N\)"):
        _cube(budgets=plytrace.Budgets(model_memory=0))
    assert _cube(budgets=plytrace.Budgets(polygons=6)).shape == (24, 24, 3)


def test_scene_files_within_budgets():
    with pytest.raises(plytrace.SceneError, match=r"Budgets\(polygons=N\)") as e:
        plytrace.Scene.from_file(CCUBE, budgets=plytrace.Budgets(polygons=2))
    assert "Budgets(polygons=N)" in e.value.message
    with pytest.raises(plytrace.SceneError, match=r"Budgets\(polygons=N\)"):
        plytrace.Scene.from_string(CCUBE.read_text(), CCUBE.parent,
                                   budgets=plytrace.Budgets(polygons=2))


# Scene text: what the program refuses.

@pytest.mark.parametrize(
    "text", ["defobj cube\n", "lookat 0 0 6 0 0 0 0\ndefobj cube\ncolor 1 0 0\n"]
)
def test_scene_text_ending_inside_defobj_is_refused(text, tmp_path):
    with pytest.raises(plytrace.SceneError, match="no `endobj` before the end of the input"):
        plytrace.Scene.from_string(text, CCUBE.parent)
    # As the same text read from a file.
    (tmp_path / "det").mkdir()
    shutil.copy(CUBE_DET, tmp_path / "det" / "cube.det")
    (tmp_path / "open.des").write_text(text)
    with pytest.raises(plytrace.SceneError, match="no `endobj` before the end of the input"):
        plytrace.Scene.from_file(tmp_path / "open.des")


def test_scene_text_must_be_a_str():
    with pytest.raises(TypeError, match="text"):
        plytrace.Scene.from_string(b"resolution 8 8\n")
    with pytest.raises(TypeError, match="directory"):
        plytrace.Scene.from_string("resolution 8 8\n", 5)


# Arrays: dtypes, layouts, indices, ragged lists.

NUMERIC = ["int8", "int16", "int32", "int64", "uint8", "uint16", "uint32", "uint64",
           "float16", "float32", "float64"]
REFUSED = ["bool", "complex64", "complex128", "U3", "S3", "datetime64[s]", "timedelta64[s]"]


COLORS = np.eye(3)[[0, 1, 2, 0, 1, 2]]
# A cube of corners 0 and 2 (which every dtype holds), seen as CAMERA sees
# the cube of corners -1 and 1.
SHIFTED = plytrace.Camera(eye=(5, -5, 4), target=(1, 1, 1))


@pytest.fixture(scope="module")
def reference():
    return _cube(vertices=CUBE_V + 1, camera=SHIFTED, face_colors=COLORS)


@pytest.mark.parametrize("dtype", NUMERIC)
def test_numeric_dtypes_give_the_same_picture(dtype, reference):
    got = [
        _cube(vertices=(CUBE_V + 1).astype(dtype), camera=SHIFTED, face_colors=COLORS),
        _cube(vertices=CUBE_V + 1, faces=CUBE_F.astype(dtype), camera=SHIFTED, face_colors=COLORS),
    ]
    if dtype != "int8":
        # Integer colours are 0 to 255 (which int8 cannot hold).
        scale = 255 if dtype[0] in "iu" else 1
        got.append(_cube(vertices=CUBE_V + 1, camera=SHIFTED,
                         face_colors=(COLORS * scale).astype(dtype)))
    for img in got:
        assert np.array_equal(img, reference)


@pytest.mark.parametrize("dtype", REFUSED)
def test_other_dtypes_raise_type_error_naming_the_argument(dtype):
    with pytest.raises(TypeError, match="vertices"):
        _cube(vertices=CUBE_V.astype(dtype))
    with pytest.raises(TypeError, match="faces"):
        _cube(faces=CUBE_F.astype(dtype))
    with pytest.raises(TypeError, match="face_colors"):
        _cube(face_colors=np.ones((6, 3)).astype(dtype))


def test_object_arrays_of_numbers_are_numbers(reference):
    assert np.array_equal(
        _cube(vertices=(CUBE_V + 1).astype(object), faces=CUBE_F.astype(object),
              camera=SHIFTED, face_colors=COLORS.astype(object)),
        reference,
    )
    with pytest.raises(TypeError, match="vertices"):
        _cube(vertices=np.array([[0, 0, {}]] * 8, dtype=object))
    with pytest.raises(ValueError, match="vertex 0 is not finite"):
        _cube(vertices=np.array([[0, 0, None]] * 8, dtype=object))
    with pytest.raises(TypeError, match="faces"):
        _cube(faces=[["a", "b", "c"]])


def test_layouts_give_the_same_picture():
    colors = COLORS
    reference = _cube(face_colors=colors)
    layouts = [
        dict(vertices=np.repeat(CUBE_V, 2, axis=0)[::2]),
        dict(vertices=np.asfortranarray(CUBE_V)),
        dict(vertices=np.ascontiguousarray(CUBE_V.T).T),
        dict(vertices=np.repeat(CUBE_V, 2, axis=1)[:, ::2]),
        dict(faces=np.repeat(CUBE_F, 3, axis=0)[::3]),
        dict(faces=np.asfortranarray(CUBE_F)),
        dict(faces=np.ascontiguousarray(CUBE_F.T).T),
        dict(faces=CUBE_F[:, ::-1][:, ::-1]),
        dict(face_colors=np.repeat(colors, 2, axis=1)[:, ::2]),
        dict(face_colors=np.asfortranarray(colors)),
    ]
    for kw in layouts:
        kw.setdefault("face_colors", colors)
        assert np.array_equal(_cube(**kw), reference), kw


BAD_INDICES = [
    np.array([[0, 1, 2**31]]), np.array([[0, 1, 2**32]]),
    np.array([[0, 1, 2**32 + 1]], dtype=np.uint64), np.array([[0, 1, 2**64 - 1]], dtype=np.uint64),
    np.array([[0, 1, -1]]), np.array([[0, -1, 2]], dtype=np.int8), [[0, 1, 2**70]], [[0, 1, -2**70]],
    np.array([[0, 1, 1e20]]), [[0, 1, 8]],
]


@pytest.mark.parametrize("faces", BAD_INDICES, ids=range(len(BAD_INDICES)))
def test_indices_out_of_range_raise_value_error_naming_the_face(faces):
    with pytest.raises(ValueError, match="face 0 names vertex"):
        _cube(faces=faces)


@pytest.mark.parametrize("value", NAN_INF)
def test_float_faces_holding_inf_or_nan_raise_value_error(value):
    for faces in (np.array([[0, 1, value]]), [[0, 1, value]]):
        with pytest.raises(ValueError, match="faces holds an index that is not finite"):
            _cube(faces=faces)
    with pytest.raises(ValueError, match="integer vertex indices, not fractions such as 2.5"):
        _cube(faces=[[0, 1, 2.5]])


def test_shapes_and_ragged_lists():
    with pytest.raises(ValueError, match="vertices"):
        _cube(vertices=[[0, 0, 0], [1, 0], [0, 1, 0]], faces=[[0, 1, 2]])
    with pytest.raises(ValueError, match="face 1 must be a list of vertex indices"):
        _cube(faces=[[0, 1, 2], [0, [1, 2], 3]])
    with pytest.raises(ValueError, match=r"faces must be an \(m, k\) array"):
        _cube(faces=np.zeros((2, 3, 3), dtype=int))
    with pytest.raises(ValueError, match=r"faces must be an \(m, k\) array"):
        _cube(faces=np.array([0, 1, 2]))
    for faces in (None, 5, "012"):
        with pytest.raises(TypeError, match="faces"):
            _cube(faces=faces)
    # Faces of different lengths are polygons of different sizes.
    tri = [list(CUBE_F[0][:3]), list(CUBE_F[0][[0, 2, 3]])] + [list(f) for f in CUBE_F[1:]]
    quads = [list(f) for f in CUBE_F]
    assert np.array_equal(_cube(faces=tri), _cube(faces=quads))


# Threads and Ctrl-C.

def test_many_threads_at_once_give_the_same_images():
    scene = plytrace.Scene.from_file(CCUBE)
    rng = np.random.default_rng(3)
    v = rng.uniform(-1, 1, (90, 3))
    f = np.arange(90).reshape(30, 3)
    mat = plytrace.Material(two_sided=True)
    jobs = [
        lambda: scene.render(size=(48, 48)),
        lambda: scene.render_vector(size=(48, 48)),
        lambda: plytrace.render(v, f, size=(40, 40), material=mat),
        lambda: plytrace.render_vector(v, f, size=(40, 40), material=mat),
    ]
    serial = [job() for job in jobs]
    with concurrent.futures.ThreadPoolExecutor(max_workers=8) as pool:
        futures = [(k, pool.submit(jobs[k])) for k in list(range(len(jobs))) * 6]
        for k, fut in futures:
            got = fut.result(timeout=300)
            if isinstance(got, np.ndarray):
                assert np.array_equal(got, serial[k]), k
            else:
                assert got == serial[k], k


CTRL_C = """
    import sys, numpy as np, plytrace
    rng = np.random.default_rng(1)
    n = 100000
    c = rng.uniform(-1, 1, (n, 1, 3))
    v = (c + rng.normal(0, 0.25, (n, 3, 3))).reshape(-1, 3)
    f = np.arange(3 * n).reshape(n, 3)
    mat = plytrace.Material(two_sided=True)
    print("start", flush=True)
    try:
        # About 8 s on 2 cores, with shadows.
        plytrace.render(v, f, material=mat, size=(4096, 4096), lights=[plytrace.Light((3, -3, 3))])
        print("finished", flush=True)
    except KeyboardInterrupt:
        print("interrupted", flush=True)
    print("after", plytrace.render(v[:30], f[:10], size=(16, 16)).shape, flush=True)
"""


def test_ctrl_c_cancels_a_raster_render():
    """SIGINT during a long raster render (not only a vector one) raises
    KeyboardInterrupt, and the next render works."""
    p = subprocess.Popen([sys.executable, "-c", textwrap.dedent(CTRL_C)],
                         stdout=subprocess.PIPE, text=True)
    assert p.stdout.readline().strip() == "start"
    time.sleep(1.0)
    p.send_signal(signal.SIGINT)
    out, _ = p.communicate(timeout=120)
    assert p.returncode == 0, out
    assert out.splitlines() == ["interrupted", "after (16, 16, 3)"], out


# The matplotlib bridge.

def _figure(build):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig = plt.figure(figsize=(3, 3), dpi=50)
    ax = fig.add_subplot(projection="3d")
    build(ax)
    return fig


def _surface(ax, z=None, **kw):
    x = np.linspace(1, 3, 9)
    X, Y = np.meshgrid(x, x)
    ax.plot_surface(X, Y, X * Y if z is None else z(X, Y), **kw)


def _log_axes(ax):
    _surface(ax, lambda X, Y: X * Y - 3)  # some of it below 0
    ax.plot([1, 2, 3], [0, 1, 2], [-1, 0, 1])
    ax.set_xscale("log")
    ax.set_zscale("log")


def _empty_collections(ax):
    from mpl_toolkits.mplot3d import art3d

    ax.add_collection3d(art3d.Poly3DCollection([]))
    ax.add_collection3d(art3d.Line3DCollection([]), autolim=False)
    ax.plot([], [], [])


HOSTILE_FIGURES = {
    "empty axes": lambda ax: None,
    "empty collections": _empty_collections,
    "empty collections and a surface": lambda ax: (_empty_collections(ax), _surface(ax)),
    "all NaN": lambda ax: _surface(ax, lambda X, Y: np.full_like(X, np.nan)),
    "NaN and inf in part": lambda ax: (
        _surface(ax, lambda X, Y: np.where(X > 2, np.nan, np.where(Y > 2.5, np.inf, X * Y))),
        ax.plot([np.nan, 1, 2, 3], [1, np.nan, 2, 2], [1, 2, np.inf, 4], "o-"),
    ),
    "masked": lambda ax: _surface(ax, lambda X, Y: np.ma.masked_where(X > 2, X * Y)),
    "log axes": _log_axes,
    "huge and tiny": lambda ax: (
        _surface(ax, lambda X, Y: X * 1e300, shade=False),
        _surface(ax, lambda X, Y: X * 1e-300, shade=False),
    ),
}
MAGIC = {"svg": b"<?xml", "pdf": b"%PDF", "png": b"\x89PNG"}


@pytest.mark.parametrize("fmt", sorted(MAGIC))
@pytest.mark.parametrize("name", sorted(HOSTILE_FIGURES))
def test_the_bridge_saves_hostile_figures(name, fmt, tmp_path):
    """No exception and no warning (numpy's included): the polygons and
    points that are not finite, or not valid on a log axis, are left out."""
    import warnings

    import plytrace.mpl

    fig = _figure(HOSTILE_FIGURES[name])
    out = tmp_path / f"plot.{fmt}"
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        plytrace.mpl.savefig(fig, out)
    assert out.read_bytes().startswith(MAGIC[fmt])
    assert [p.name for p in tmp_path.iterdir()] == [out.name]
    _close(fig)


def _close(fig):
    import matplotlib.pyplot as plt

    plt.close(fig)


@pytest.mark.parametrize(
    "value, error", [(np.nan, ValueError), (np.inf, ValueError), (-1, ValueError),
                     ("0.3", TypeError), (None, TypeError), (1j, TypeError)],
)
def test_the_bridge_refuses_bad_seam_widths(value, error):
    import io

    import plytrace.mpl

    fig = _figure(_surface)
    for call in (
        lambda: plytrace.mpl.savefig(fig, io.BytesIO(), format="svg", seam_width=value),
        lambda: plytrace.mpl.fix(fig, seam_width=value),
    ):
        with pytest.raises(error, match="seam_width"):
            call()
    _close(fig)


def test_the_bridge_names_files_as_matplotlib_does(tmp_path):
    import plytrace.mpl

    fig = _figure(_surface)
    plytrace.mpl.savefig(fig, tmp_path / "plot")
    plytrace.mpl.savefig(fig, str(tmp_path / "other.png"), format="pdf")
    assert (tmp_path / "plot.png").read_bytes().startswith(MAGIC["png"])
    assert (tmp_path / "other.png").read_bytes().startswith(MAGIC["pdf"])
    _close(fig)
