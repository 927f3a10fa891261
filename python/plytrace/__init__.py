"""plytrace: a list-priority renderer (A. Garcia, MIT 1986) for Python.

Render a mesh given as numpy arrays, or a scene in plytrace's scene
descriptor language (``.des``), to an image or to exact vector graphics::

    import numpy as np, plytrace
    vertices = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float)
    faces = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    image = plytrace.render(vertices, faces, face_colors=np.eye(4)[:, :3])
    svg = plytrace.render_vector(vertices, faces, format="svg")

Visible surfaces come from the Newell-Newell-Sancha sort with face
splitting, so the SVG, PDF and TikZ output is right where surfaces
interpenetrate. ``plytrace.mpl`` uses the same sort to draw matplotlib's
3-D plots correctly.

The work runs with the GIL released; Ctrl-C (``KeyboardInterrupt``)
cancels a render (every render in flight in the process). Bad input
raises ``ValueError`` (``SceneError``, a subclass, for scene files, with
``file``, ``line`` and ``column``) or ``TypeError`` naming the argument;
a mesh or an image over the :class:`Budgets` raises ``MemoryError``.
Files are written whole or not at all.
"""

from __future__ import annotations

import math
import numbers
import operator
import os
from dataclasses import dataclass, fields
from typing import Optional, Sequence, Tuple, Union

import numpy as np

from . import _native
from ._native import NativeScene as _NativeScene
from ._native import SceneError
from ._native import __version__

__all__ = [
    "Budgets",
    "Camera",
    "Light",
    "Material",
    "Scene",
    "SceneError",
    "render",
    "render_vector",
    "__version__",
]

_FORMATS = ("svg", "pdf", "tex")

_MAX_SIDE: int = _native.MAX_IMAGE_SIDE
_MAX_PIXELS: int = _native.MAX_IMAGE_PIXELS
_DEFAULT_BUDGETS = _native.default_budgets()


@dataclass(frozen=True)
class Budgets:
    """Limits on the work of reading and rendering, as the ``plytrace``
    program's ``--max-*`` flags (the same names and units): a mesh, a
    scene or a render over one is refused before the memory is taken,
    with ``MemoryError`` (``ValueError`` for the limits of work, such as
    ``rays``) that names the field that raises it::

        plytrace.render(v, f, budgets=plytrace.Budgets(polygons=10_000_000))

    ``polygons``: of the scene; ``call_depth``: nesting of ``call``;
    ``tree_nodes``: fragments of the virtual image tree; ``splits``: face
    splits of one NNS sort; ``pixels``: of one image; ``frame_memory``:
    MiB of a whole frame held at once; ``overdraw``: records per pixel
    one scan conversion tiles; ``pair_tests``: of one modelling
    operation; ``model_memory``: MiB of one object's vertices and
    polygons; ``rays``: of one ray-traced render.
    """

    polygons: int = _DEFAULT_BUDGETS["polygons"]
    call_depth: int = _DEFAULT_BUDGETS["call_depth"]
    tree_nodes: int = _DEFAULT_BUDGETS["tree_nodes"]
    splits: int = _DEFAULT_BUDGETS["splits"]
    pixels: int = _DEFAULT_BUDGETS["pixels"]
    frame_memory: int = _DEFAULT_BUDGETS["frame_memory"]
    overdraw: int = _DEFAULT_BUDGETS["overdraw"]
    pair_tests: int = _DEFAULT_BUDGETS["pair_tests"]
    model_memory: int = _DEFAULT_BUDGETS["model_memory"]
    rays: int = _DEFAULT_BUDGETS["rays"]


@dataclass
class Camera:
    """Where the scene is seen from.

    ``eye`` looks at ``target`` with ``up`` shown up. A perspective of
    ``fovy`` degrees (vertical), or with ``ortho=(left, right, bottom,
    top)`` (in the eye's coordinates) an orthographic view. ``near`` and
    ``far`` are the distances drawn. ``Camera.fit(vertices)`` frames a
    mesh.
    """

    eye: Sequence[float]
    target: Sequence[float] = (0.0, 0.0, 0.0)
    up: Sequence[float] = (0.0, 0.0, 1.0)
    fovy: float = 45.0
    near: float = 0.01
    far: float = 10_000.0
    ortho: Optional[Sequence[float]] = None

    @classmethod
    def fit(
        cls,
        vertices,
        direction: Sequence[float] = (1.0, -1.6, 1.0),
        fovy: float = 30.0,
    ) -> "Camera":
        """A perspective camera looking along ``-direction`` at the centre
        of ``vertices``' bounding box, from far enough to see all of it."""
        v = _vertices(vertices)
        fovy = _number(fovy, "fovy")
        if not 0 < fovy < 180:
            raise ValueError(f"fovy must lie between 0 and 180 degrees, not {fovy}")
        lo, hi = v.min(axis=0), v.max(axis=0)
        centre = (lo + hi) / 2
        radius = max(float(_norm(hi - lo)) / 2, 1e-9)
        d = np.array(_vec3(direction, "direction"))
        if _norm(d) == 0:
            raise ValueError("direction must not be (0, 0, 0)")
        d = d / _norm(d)
        distance = radius / math.sin(math.radians(fovy) / 2) * 1.05
        return cls(
            eye=tuple(centre + d * distance),
            target=tuple(centre),
            fovy=fovy,
            near=max(distance - 2 * radius, distance * 1e-3),
            far=distance + 2 * radius,
        )


@dataclass
class Light:
    """A light at ``position`` of ``color`` (0 to 1). ``shadows``: it casts
    shadows (the scene language's ``Point`` light; else ``Diffuse``).
    ``range``: the distance at which its light falls to nothing."""

    position: Sequence[float]
    color: Sequence[float] = (1.0, 1.0, 1.0)
    shadows: bool = True
    range: float = 10_000.0


@dataclass
class Material:
    """A surface, as the scene language's commands set it.

    ``color`` (0 to 1), ``diffuse`` (the rest of the light, ``1 -
    diffuse``, is ambient), ``specular`` and ``shininess`` (Phong
    highlights), ``reflectance`` (a mirror: the scene behind it is drawn
    reflected), ``transmittance`` and ``index`` (glass: refraction),
    ``transparency``. ``two_sided``: back faces are drawn (an open
    surface); ``smooth``: vertex normals are interpolated.
    """

    color: Sequence[float] = (0.8, 0.8, 0.8)
    diffuse: float = 0.6
    specular: float = 0.0
    shininess: float = 0.0
    reflectance: float = 0.0
    transmittance: float = 0.0
    index: float = 1.0
    transparency: float = 0.0
    two_sided: bool = False
    smooth: bool = False


def _norm(v) -> float:
    """Euclidean length, without numpy's BLAS (whose threads would spin
    beside the renderer's)."""
    return math.sqrt(sum(float(x) * float(x) for x in np.asarray(v).reshape(-1)))


def _array(value, what: str) -> np.ndarray:
    """``value`` as an array of real numbers (integers or floats), without
    a copy where it is one already. Booleans, complex numbers, strings,
    dates and objects that are not numbers raise ``TypeError``; a ragged
    list raises ``ValueError``."""
    try:
        a = np.asarray(value)
    except (TypeError, ValueError) as e:
        raise ValueError(f"{what} must be an array of numbers: {e}") from None
    kind = a.dtype.kind
    if kind == "O":
        try:
            a = a.astype(np.float64)
        except OverflowError:
            raise ValueError(f"{what} holds a number too large for a float") from None
        except (TypeError, ValueError):
            raise TypeError(f"{what} must hold real numbers, not arbitrary objects") from None
    elif kind not in "iuf":
        raise TypeError(f"{what} must hold real numbers (integers or floats), not {a.dtype}")
    return a


def _number(value, what: str) -> float:
    """One finite real number (not a bool, a string or complex)."""
    if isinstance(value, np.ndarray) and value.ndim == 0:
        value = value[()]
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
        raise TypeError(f"{what} must be a number, not {type(value).__name__}")
    try:
        v = float(value)
    except OverflowError:
        raise ValueError(f"{what} is too large: {value}") from None
    if not math.isfinite(v):
        raise ValueError(f"{what} must be finite, not {v}")
    return v


def _whole(value, what: str) -> int:
    """One whole number (an int or a numpy integer, not a bool or float)."""
    if isinstance(value, (bool, np.bool_)):
        raise TypeError(f"{what} must be a whole number, not bool")
    try:
        return operator.index(value)
    except TypeError:
        raise TypeError(f"{what} must be a whole number, not {value!r}") from None


def _vertices(vertices) -> np.ndarray:
    v = _array(vertices, "vertices")
    if v.ndim != 2 or v.shape[1] != 3:
        raise ValueError(f"vertices must have shape (n, 3), not {v.shape}")
    if len(v) == 0:
        raise ValueError("vertices is empty: a mesh needs at least 3 vertices")
    v = np.ascontiguousarray(v, dtype=np.float64)
    bad = ~np.isfinite(v).all(axis=1)
    if bad.any():
        i = int(np.argmax(bad))
        raise ValueError(f"vertex {i} is not finite: {v[i].tolist()}")
    return v


def _face_rows(faces, precheck):
    """Faces as an ``(m, k)`` array or a list of 1-D index arrays, with the
    number of faces and of indices, checked for shape (not yet values).
    ``precheck(faces, corners)`` is called with the counts of a list
    before its rows are converted."""
    if isinstance(faces, np.ndarray) and faces.dtype.kind != "O":
        if faces.ndim != 2:
            raise ValueError(
                "faces must be an (m, k) array or a list of index lists, "
                f"not an array of shape {faces.shape}"
            )
        if faces.shape[0] == 0:
            raise ValueError("faces is empty: a mesh needs at least one face")
        if faces.shape[1] < 3:
            raise ValueError(f"faces must have shape (m, k) with k >= 3, not {faces.shape}")
        return faces, faces.shape[0], faces.size
    if isinstance(faces, (str, bytes)) or not hasattr(faces, "__iter__"):
        raise TypeError(
            f"faces must be an (m, k) array or a list of index lists, not {type(faces).__name__}"
        )
    faces = list(faces)
    precheck(len(faces), 3 * len(faces))
    rows = []
    for i, r in enumerate(faces):
        try:
            a = np.asarray(r)
        except (TypeError, ValueError):
            raise ValueError(f"face {i} must be a list of vertex indices") from None
        if a.ndim != 1:
            raise ValueError(f"face {i} must be a list of vertex indices, not {r!r}")
        if len(a) < 3:
            raise ValueError(f"face {i} has {len(a)} vertices; a face needs 3")
        rows.append(a)
    if not rows:
        raise ValueError("faces is empty: a mesh needs at least one face")
    return rows, len(rows), sum(len(a) for a in rows)


def _indices(a: np.ndarray) -> np.ndarray:
    """Vertex indices as integers: integer arrays as they are, floats that
    are whole numbers; others refused."""
    kind = a.dtype.kind
    if kind == "O":
        try:
            a = a.astype(np.float64)
        except OverflowError:
            raise ValueError("faces holds an index too large for any mesh") from None
        except (TypeError, ValueError):
            raise TypeError("faces must hold integer vertex indices, not arbitrary objects") from None
        kind = "f"
    if kind == "f":
        bad = ~np.isfinite(a)
        if bad.any():
            raise ValueError(f"faces holds an index that is not finite: {a[np.argmax(bad)]}")
        frac = a != np.round(a)
        if frac.any():
            raise ValueError(
                f"faces must hold integer vertex indices, not fractions such as {a[np.argmax(frac)]}"
            )
    elif kind not in "iu":
        raise TypeError(f"faces must hold integer vertex indices, not {a.dtype}")
    return a


def _faces(rows, n_vertices: int) -> Tuple[np.ndarray, np.ndarray]:
    """Faces (from :func:`_face_rows`) as flat indices and sizes, checked."""
    if isinstance(rows, np.ndarray):
        indices = _indices(rows.reshape(-1))
        sizes = np.full(rows.shape[0], rows.shape[1], dtype=np.uint32)
    else:
        sizes = np.array([len(r) for r in rows], dtype=np.uint32)
        indices = _indices(np.concatenate(rows))
    out = (indices < 0) | (indices >= n_vertices)
    if out.any():
        k = int(np.argmax(out))
        face = int(np.searchsorted(np.cumsum(sizes, dtype=np.int64), k, side="right"))
        raise ValueError(
            f"face {face} names vertex {int(indices[k])}, but there are "
            f"{n_vertices} vertices (indices run from 0 to {n_vertices - 1})"
        )
    return np.ascontiguousarray(indices, dtype=np.uint32), sizes


def _colors(colors, what: str) -> np.ndarray:
    c = _array(colors, what)
    if c.ndim == 1 and c.shape[0] in (3, 4):
        c = c[None, :]
    if c.ndim != 2 or c.shape[1] not in (3, 4):
        raise ValueError(f"{what} must have shape (n, 3) or (n, 4), not {c.shape}")
    integer = c.dtype.kind in "iu"
    c = c[:, :3].astype(np.float64)
    if integer:
        c = c / 255.0
    if not np.isfinite(c).all():
        raise ValueError(f"{what} holds a value that is not finite")
    if (c < 0).any() or (c > 1).any():
        raise ValueError(f"{what} must lie in 0 to 1 (or 0 to 255 as integers)")
    return np.ascontiguousarray(c)


def _rgb(value, what: str) -> Tuple[float, float, float]:
    c = _colors(value, what)
    if len(c) != 1:
        raise ValueError(f"{what} must be one colour (r, g, b)")
    r, g, b = (float(x) for x in c[0])
    return r, g, b


def _size(size, what: str = "size") -> Tuple[int, int]:
    """``(width, height)``: whole numbers, each side 1 to
    ``MAX_IMAGE_SIDE`` and at most ``MAX_IMAGE_PIXELS`` in all (as the
    scene language's ``resolution``)."""
    if isinstance(size, (str, bytes)):
        raise TypeError(f"{what} must be (width, height), not {size!r}")
    try:
        w, h = size
    except (TypeError, ValueError):
        raise TypeError(f"{what} must be (width, height), not {size!r}") from None
    w, h = _whole(w, f"{what}[0] (width)"), _whole(h, f"{what}[1] (height)")
    if w < 1 or h < 1:
        raise ValueError(f"{what} must be positive, not {size!r}")
    if w > _MAX_SIDE or h > _MAX_SIDE or w * h > _MAX_PIXELS:
        raise ValueError(
            f"{what} {w} x {h}: each side must be 1 to {_MAX_SIDE} and the total at most "
            f"{_MAX_PIXELS} pixels"
        )
    return w, h


def _vec3(v, what: str) -> Tuple[float, float, float]:
    a = _array(v, what).astype(np.float64).reshape(-1)
    if a.shape != (3,) or not np.isfinite(a).all():
        raise ValueError(f"{what} must be three finite numbers, not {v!r}")
    x, y, z = (float(c) for c in a)
    return x, y, z


def _unit(value, what: str) -> float:
    v = _number(value, what)
    if not 0.0 <= v <= 1.0:
        raise ValueError(f"{what} must lie in 0 to 1, not {v}")
    return v


def _material(m) -> Tuple[Tuple[float, float, float], list]:
    """A material's colour and coefficients, checked as the scene
    language's commands check them."""
    if not isinstance(m, Material):
        raise TypeError(f"material must be a plytrace.Material, not {type(m).__name__}")
    shininess = _number(m.shininess, "material.shininess")
    if shininess < 0:
        raise ValueError(f"material.shininess must be 0 or more, not {shininess}")
    index = _number(m.index, "material.index")
    if index <= 0:
        raise ValueError(f"material.index must be more than 0, not {index}")
    coefficients = [
        _unit(m.diffuse, "material.diffuse"),
        _unit(m.specular, "material.specular"),
        shininess,
        _unit(m.reflectance, "material.reflectance"),
        _unit(m.transmittance, "material.transmittance"),
        index,
        _unit(m.transparency, "material.transparency"),
    ]
    return _rgb(m.color, "material.color"), coefficients


def _light(light, what: str):
    """A light's arguments for the native scene, checked as the scene
    language's ``light`` checks them."""
    if not isinstance(light, Light):
        raise TypeError(f"lights must be plytrace.Light objects, not {type(light).__name__}")
    color = _vec3(light.color, f"{what}.color")
    if min(color) < 0:
        raise ValueError(f"{what}.color must not be negative, not {color}")
    range_ = _number(light.range, f"{what}.range")
    if range_ <= 0:
        raise ValueError(f"{what}.range must be more than 0, not {range_}")
    return _vec3(light.position, f"{what}.position"), color, range_, bool(light.shadows)


def _camera(cam):
    """A camera's arguments for the native scene, checked."""
    if not isinstance(cam, Camera):
        raise TypeError(f"camera must be a plytrace.Camera, not {type(cam).__name__}")
    eye = _vec3(cam.eye, "camera.eye")
    target = _vec3(cam.target, "camera.target")
    up = _vec3(cam.up, "camera.up")
    near = _number(cam.near, "camera.near")
    far = _number(cam.far, "camera.far")
    ortho = None
    if cam.ortho is None:
        fovy = _number(cam.fovy, "camera.fovy")
        if not 0 < fovy < 180:
            raise ValueError(f"camera.fovy must lie between 0 and 180 degrees, not {fovy}")
        if not 0 < near < far:
            raise ValueError(f"camera.near and camera.far must be 0 < near < far, not {near}, {far}")
    else:
        o = _array(cam.ortho, "camera.ortho").reshape(-1)
        if o.shape != (4,) or not np.isfinite(o).all():
            raise ValueError(f"camera.ortho must be four finite numbers (left, right, bottom, top), not {cam.ortho!r}")
        left, right, bottom, top = (float(x) for x in o)
        ortho = (left, right, bottom, top)
        fovy = 45.0
    return eye, target, up, fovy, near, far, ortho


def _budgets(budgets) -> Optional[dict]:
    """The fields of a :class:`Budgets` for the native scene (``None``:
    the defaults), checked."""
    if budgets is None:
        return None
    if not isinstance(budgets, Budgets):
        raise TypeError(f"budgets must be a plytrace.Budgets, not {type(budgets).__name__}")
    out = {}
    for f in fields(budgets):
        n = _whole(getattr(budgets, f.name), f"budgets.{f.name}")
        if not 0 <= n < 2**64:
            raise ValueError(f"budgets.{f.name} must be 0 to 2**64 - 1, not {n}")
        out[f.name] = n
    return out


def _path(path, what: str = "path") -> str:
    try:
        p = os.fspath(path)
    except TypeError:
        raise TypeError(f"{what} must be a file name (str or os.PathLike), not {type(path).__name__}") from None
    p = os.fsdecode(p)
    if not p:
        raise ValueError(f"{what} is empty")
    return p


def _mesh_scene(
    vertices,
    faces,
    colors,
    face_colors,
    vertex_colors,
    material,
    camera,
    lights,
    size,
    background,
    budgets,
) -> _NativeScene:
    b = _budgets(budgets)
    if material is not None and not isinstance(material, Material):
        raise TypeError(f"material must be a plytrace.Material, not {type(material).__name__}")
    # The budgets first, from the arrays' lengths alone: nothing is copied
    # for a mesh over them.
    v = _array(vertices, "vertices")
    n_vertices = len(v) if v.ndim else 0

    def check(n_faces: int, n_indices: int) -> None:
        _native.check_mesh("mesh", n_vertices, n_faces, n_indices, b)

    rows, n_faces, n_indices = _face_rows(faces, check)
    check(n_faces, n_indices)
    v = _vertices(v)
    indices, sizes = _faces(rows, len(v))
    if colors is not None:
        if face_colors is not None or vertex_colors is not None:
            raise ValueError("give colors, or face_colors / vertex_colors, not both")
        c = _colors(colors, "colors")
        if len(c) == len(sizes) and len(c) == len(v):
            raise ValueError(
                f"colors has {len(c)} rows, both the number of faces and of vertices: "
                "say which with face_colors= or vertex_colors="
            )
        if len(c) == len(sizes):
            face_colors = c
        elif len(c) == len(v):
            vertex_colors = c
        elif len(c) == 1:
            material = Material(**{**(material or Material()).__dict__, "color": tuple(c[0])})
        else:
            raise ValueError(
                f"colors has {len(c)} rows: expected one per face ({len(sizes)}), "
                f"one per vertex ({len(v)}) or one"
            )
    if face_colors is not None:
        face_colors = _colors(face_colors, "face_colors")
    if vertex_colors is not None:
        vertex_colors = _colors(vertex_colors, "vertex_colors")
    color, coefficients = _material(material if material is not None else Material())
    w, h = _size(size)
    eye, target, up, fovy, near, far, ortho = _camera(
        camera if camera is not None else Camera.fit(v)
    )
    scene = _NativeScene.new(eye, target, up, fovy, near, far, ortho, w, h)
    if b is not None:
        scene.set_budgets(b)
    if lights is None:
        e, t, u = np.array(eye), np.array(target), np.array(up)
        back = e - t
        side = np.cross(u, back)
        n = _norm(side)
        side = side / n * _norm(back) * 0.5 if n > 0 else side
        lights = [Light(tuple(e - side + u * _norm(back) * 0.5), shadows=False)]
    if isinstance(lights, Light) or not hasattr(lights, "__iter__"):
        raise TypeError(f"lights must be a list of plytrace.Light, not {type(lights).__name__}")
    for i, light in enumerate(lights):
        scene.add_light(*_light(light, f"lights[{i}]"))
    scene.set_background(_rgb(background, "background"))
    m = material if material is not None else Material()
    scene.add_mesh(
        "mesh",
        v,
        indices,
        sizes,
        face_colors,
        vertex_colors,
        color,
        coefficients,
        bool(m.two_sided),
        bool(m.smooth),
    )
    return scene


def render(
    vertices,
    faces,
    *,
    colors=None,
    face_colors=None,
    vertex_colors=None,
    material: Optional[Material] = None,
    camera: Optional[Camera] = None,
    lights: Optional[Sequence[Light]] = None,
    size: Tuple[int, int] = (512, 512),
    background=(1.0, 1.0, 1.0),
    antialias: bool = True,
    shadows: bool = True,
    budgets: Optional[Budgets] = None,
) -> np.ndarray:
    """Renders a mesh to an ``(height, width, 3)`` uint8 array.

    ``vertices``: ``(n, 3)`` numbers. ``faces``: ``(m, k)`` integer
    indices into the vertices (``k >= 3``), or a list of index lists of
    any lengths, counter-clockwise seen from outside (the convention of
    OBJ, PLY and most numpy tools); each face must be planar and may be
    concave. ``colors``: one colour per face or per vertex (Gouraud
    shaded), or one for all, as ``(r, g, b)`` in 0 to 1 (or 0 to 255 as
    integers; a fourth column is ignored); ``face_colors`` and
    ``vertex_colors`` say which when the counts are equal. ``material``: a
    :class:`Material`. ``camera``: a :class:`Camera`; by default one that
    frames the mesh. ``lights``: :class:`Light` objects; by default one
    above and to the left of the camera that casts no shadow.
    ``background``: a colour. ``size``: ``(width, height)``, each 1 to
    65,536 and at most 2^28 pixels in all.
    ``antialias``: Garcia's multi-level pixel masks; ``False`` samples
    each pixel once. ``shadows``: lights that cast shadows do.
    ``budgets``: the limits on the work (:class:`Budgets`).

    Raises ``ValueError`` for arrays of the wrong shape, values that are
    not finite or out of range, empty meshes and indices out of range;
    ``TypeError`` for arrays of booleans, complex numbers, strings or
    other objects; ``MemoryError`` for a mesh or an image over the
    budgets.
    """
    scene = _mesh_scene(
        vertices, faces, colors, face_colors, vertex_colors, material, camera, lights,
        size, background, budgets,
    )
    return scene.render(None, bool(antialias), bool(shadows))


def _write_or_return(data: bytes, path) -> Optional[bytes]:
    """``data``, or (given a ``path``) ``None`` once ``data`` is written
    there through the library's atomic writer: a temporary file beside
    it, renamed into place once whole, so that an earlier file survives a
    failed write (a full disk) intact. A file this process has read as an
    input (a scene, an object file) is not written over."""
    if path is None:
        return data
    _native.write_file(_path(path), data)
    return None


def _format(format: Optional[str], path) -> str:
    if format is None and path is not None:
        format = os.path.splitext(_path(path))[1].lstrip(".").lower()
    if not isinstance(format, str):
        raise TypeError(f"format must be a str, not {type(format).__name__}")
    if format not in _FORMATS:
        raise ValueError(f'format {format!r}: expected "svg", "pdf" or "tex"')
    return format


def render_vector(
    vertices,
    faces,
    *,
    format: Optional[str] = None,
    path: Union[str, os.PathLike, None] = None,
    colors=None,
    face_colors=None,
    vertex_colors=None,
    material: Optional[Material] = None,
    camera: Optional[Camera] = None,
    lights: Optional[Sequence[Light]] = None,
    size: Tuple[int, int] = (512, 512),
    background=(1.0, 1.0, 1.0),
    shadows: bool = True,
    budgets: Optional[Budgets] = None,
) -> Optional[bytes]:
    """Renders a mesh as vector graphics: ``format`` ``"svg"``, ``"pdf"``
    or ``"tex"`` (a TikZ picture), by default from ``path``'s extension,
    else SVG. Returns the file's bytes, or writes them to ``path`` (whole
    or not at all) and returns ``None``. The polygons are split and
    ordered by the NNS sort, so the picture is exact; ``size`` is its size
    in user units (pixels). The other arguments are those of
    :func:`render`.
    """
    fmt = _format(format if format is not None or path is not None else "svg", path)
    scene = _mesh_scene(
        vertices, faces, colors, face_colors, vertex_colors, material, camera, lights,
        size, background, budgets,
    )
    return _write_or_return(scene.render_vector(fmt, None, bool(shadows)), path)


class Scene:
    """A scene in plytrace's scene descriptor language (``.des``).

    ``Scene.from_file(path)`` reads a file; ``Scene.from_string(text,
    directory=".")`` reads its text (object files named in it are looked
    up in ``directory``). Both refuse what ``plytrace -f`` refuses. A scene
    shows itself in Jupyter (as PNG or SVG). Errors in the scene raise
    :class:`SceneError` with the file, line and column.
    """

    #: Largest side of the picture Jupyter shows, in pixels.
    repr_size: int = 512

    def __init__(self, native: _NativeScene):
        self._native = native

    @classmethod
    def from_file(
        cls, path: Union[str, os.PathLike], *, budgets: Optional[Budgets] = None
    ) -> "Scene":
        """Reads a scene descriptor file (its ``run`` commands are not
        acted on: call :meth:`render`) within ``budgets``, which the scene
        keeps for its renders."""
        return cls(_NativeScene.from_file(_path(path), _budgets(budgets)))

    @classmethod
    def from_string(
        cls,
        text: str,
        directory: Union[str, os.PathLike] = ".",
        *,
        budgets: Optional[Budgets] = None,
    ) -> "Scene":
        """Reads a scene from the text of a scene descriptor file."""
        if not isinstance(text, str):
            raise TypeError(f"text must be a str, not {type(text).__name__}")
        return cls(
            _NativeScene.from_text(text, _path(directory, "directory"), _budgets(budgets))
        )

    @property
    def size(self) -> Tuple[int, int]:
        """The picture's size the scene sets, (width, height)."""
        return self._native.size()

    def render(
        self,
        *,
        size: Optional[Tuple[int, int]] = None,
        antialias: bool = True,
        shadows: bool = True,
        budgets: Optional[Budgets] = None,
    ) -> np.ndarray:
        """Renders to an ``(height, width, 3)`` uint8 array, at ``size`` or
        the scene's own resolution, within ``budgets`` (by default those
        the scene was read within)."""
        return self._native.render(
            None if size is None else _size(size), bool(antialias), bool(shadows),
            _budgets(budgets),
        )

    def render_vector(
        self,
        format: Optional[str] = None,
        path: Union[str, os.PathLike, None] = None,
        *,
        size: Optional[Tuple[int, int]] = None,
        shadows: bool = True,
        budgets: Optional[Budgets] = None,
    ) -> Optional[bytes]:
        """Renders as SVG, PDF or TikZ (``format`` ``"svg"``, ``"pdf"``,
        ``"tex"``; by default from ``path``'s extension, else SVG). Returns
        the bytes, or writes ``path`` (whole or not at all; never over an
        input the scene was read from) and returns ``None``."""
        fmt = _format(format if format is not None or path is not None else "svg", path)
        data = self._native.render_vector(
            fmt, None if size is None else _size(size), bool(shadows), _budgets(budgets)
        )
        return _write_or_return(data, path)

    def _repr_size(self) -> Tuple[int, int]:
        w, h = self.size
        k = min(1.0, self.repr_size / max(w, h))
        return max(1, round(w * k)), max(1, round(h * k))

    def _repr_png_(self) -> bytes:
        return self._native.render_png(self._repr_size(), True, True)

    def _repr_svg_(self) -> str:
        svg = self.render_vector("svg", size=self._repr_size())
        assert svg is not None
        return svg.decode()

    def __repr__(self) -> str:
        w, h = self.size
        return f"<plytrace.Scene {w} x {h}>"
