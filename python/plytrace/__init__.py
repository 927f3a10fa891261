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
cancels a render. Bad input raises ``ValueError`` (``SceneError``, a
subclass, for scene files, with ``file``, ``line`` and ``column``).
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, field
from typing import Optional, Sequence, Tuple, Union

import numpy as np

from ._native import NativeScene as _NativeScene
from ._native import SceneError
from ._native import __version__

__all__ = [
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
        lo, hi = v.min(axis=0), v.max(axis=0)
        centre = (lo + hi) / 2
        radius = max(float(_norm(hi - lo)) / 2, 1e-9)
        d = np.asarray(direction, dtype=float)
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


def _vertices(vertices) -> np.ndarray:
    try:
        v = np.asarray(vertices, dtype=np.float64)
    except (TypeError, ValueError) as e:
        raise ValueError(f"vertices must be an (n, 3) array of numbers: {e}") from None
    if v.ndim != 2 or v.shape[1] != 3:
        raise ValueError(f"vertices must have shape (n, 3), not {v.shape}")
    if len(v) == 0:
        raise ValueError("vertices is empty: a mesh needs at least 3 vertices")
    bad = ~np.isfinite(v).all(axis=1)
    if bad.any():
        i = int(np.argmax(bad))
        raise ValueError(f"vertex {i} is not finite: {v[i].tolist()}")
    return np.ascontiguousarray(v)


def _faces(faces, n_vertices: int) -> Tuple[np.ndarray, np.ndarray]:
    """Faces as flat indices and sizes, checked."""
    if isinstance(faces, np.ndarray) and faces.ndim == 2:
        f = faces
        if f.shape[0] == 0:
            raise ValueError("faces is empty: a mesh needs at least one face")
        if f.shape[1] < 3:
            raise ValueError(f"faces must have shape (m, k) with k >= 3, not {f.shape}")
        if not np.issubdtype(f.dtype, np.integer):
            if not np.issubdtype(f.dtype, np.floating) or np.any(f != np.round(f)):
                raise ValueError(f"faces must hold integer vertex indices, not {f.dtype}")
        indices = f.reshape(-1)
        sizes = np.full(f.shape[0], f.shape[1], dtype=np.uint32)
    else:
        rows = list(faces)
        if not rows:
            raise ValueError("faces is empty: a mesh needs at least one face")
        sizes = np.array([len(r) for r in rows], dtype=np.uint32)
        short = np.flatnonzero(sizes < 3)
        if len(short):
            i = int(short[0])
            raise ValueError(f"face {i} has {sizes[i]} vertices; a face needs 3")
        indices = np.concatenate([np.asarray(r).reshape(-1) for r in rows])
        if not np.issubdtype(indices.dtype, np.integer):
            raise ValueError(f"faces must hold integer vertex indices, not {indices.dtype}")
    indices = np.asarray(indices)
    out = (indices < 0) | (indices >= n_vertices)
    if out.any():
        k = int(np.argmax(out))
        face = int(np.searchsorted(np.cumsum(sizes), k, side="right"))
        raise ValueError(
            f"face {face} names vertex {int(indices[k])}, but there are "
            f"{n_vertices} vertices (indices run from 0 to {n_vertices - 1})"
        )
    return np.ascontiguousarray(indices, dtype=np.uint32), sizes


def _colors(colors, what: str) -> np.ndarray:
    try:
        c = np.asarray(colors)
    except (TypeError, ValueError) as e:
        raise ValueError(f"{what} must be an (n, 3) array: {e}") from None
    if c.ndim == 1 and c.shape[0] in (3, 4):
        c = c[None, :]
    if c.ndim != 2 or c.shape[1] not in (3, 4):
        raise ValueError(f"{what} must have shape (n, 3) or (n, 4), not {c.shape}")
    integer = np.issubdtype(c.dtype, np.integer)
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


def _size(size) -> Tuple[int, int]:
    try:
        w, h = size
        w, h = int(w), int(h)
    except (TypeError, ValueError):
        raise ValueError(f"size must be (width, height), not {size!r}") from None
    if w < 1 or h < 1:
        raise ValueError(f"size must be positive, not {size!r}")
    return w, h


def _vec3(v, what: str) -> Tuple[float, float, float]:
    a = np.asarray(v, dtype=float).reshape(-1)
    if a.shape != (3,) or not np.isfinite(a).all():
        raise ValueError(f"{what} must be three finite numbers, not {v!r}")
    x, y, z = (float(c) for c in a)
    return x, y, z


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
) -> _NativeScene:
    v = _vertices(vertices)
    indices, sizes = _faces(faces, len(v))
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
    m = material if material is not None else Material()
    if not isinstance(m, Material):
        raise ValueError(f"material must be a plytrace.Material, not {type(m).__name__}")
    w, h = _size(size)
    cam = camera if camera is not None else Camera.fit(v)
    if not isinstance(cam, Camera):
        raise ValueError(f"camera must be a plytrace.Camera, not {type(cam).__name__}")
    ortho = None if cam.ortho is None else tuple(float(x) for x in cam.ortho)
    if ortho is not None and len(ortho) != 4:
        raise ValueError("camera.ortho must be (left, right, bottom, top)")
    scene = _NativeScene.new(
        _vec3(cam.eye, "camera.eye"),
        _vec3(cam.target, "camera.target"),
        _vec3(cam.up, "camera.up"),
        float(cam.fovy),
        float(cam.near),
        float(cam.far),
        ortho,
        w,
        h,
    )
    if lights is None:
        eye = np.array(_vec3(cam.eye, "camera.eye"))
        target = np.array(_vec3(cam.target, "camera.target"))
        up = np.array(_vec3(cam.up, "camera.up"))
        back = eye - target
        side = np.cross(up, back)
        n = _norm(side)
        side = side / n * _norm(back) * 0.5 if n > 0 else side
        lights = [Light(tuple(eye - side + up * _norm(back) * 0.5), shadows=False)]
    for light in lights:
        if not isinstance(light, Light):
            raise ValueError(f"lights must be plytrace.Light objects, not {type(light).__name__}")
        scene.add_light(
            _vec3(light.position, "light.position"),
            _vec3(light.color, "light.color"),
            float(light.range),
            bool(light.shadows),
        )
    scene.set_background(_rgb(background, "background"))
    scene.add_mesh(
        "mesh",
        v,
        indices,
        sizes,
        face_colors,
        vertex_colors,
        _rgb(m.color, "material.color"),
        [
            float(m.diffuse),
            float(m.specular),
            float(m.shininess),
            float(m.reflectance),
            float(m.transmittance),
            float(m.index),
            float(m.transparency),
        ],
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
) -> np.ndarray:
    """Renders a mesh to an ``(height, width, 3)`` uint8 array.

    ``vertices``: ``(n, 3)`` floats. ``faces``: ``(m, k)`` integer indices
    into the vertices (``k >= 3``), or a list of index lists of any
    lengths, counter-clockwise seen from outside (the convention of OBJ,
    PLY and most numpy tools); each face must be planar and may be
    concave. ``colors``: one colour per face or per vertex (Gouraud
    shaded), or one for all, as ``(r, g, b)`` in 0 to 1 (or 0 to 255 as
    integers; a fourth column is ignored); ``face_colors`` and
    ``vertex_colors`` say which when the counts are equal. ``material``: a
    :class:`Material`. ``camera``: a :class:`Camera`; by default one that
    frames the mesh. ``lights``: :class:`Light` objects; by default one
    above and to the left of the camera that casts no shadow.
    ``background``: a colour.
    ``antialias``: Garcia's multi-level pixel masks; ``False`` samples
    each pixel once. ``shadows``: lights that cast shadows do.

    Raises ``ValueError`` for arrays of the wrong shape, values that are
    not finite, empty meshes and indices out of range.
    """
    scene = _mesh_scene(
        vertices, faces, colors, face_colors, vertex_colors, material, camera, lights,
        size, background,
    )
    return scene.render(None, bool(antialias), bool(shadows))


def _write_or_return(data: bytes, path) -> Optional[bytes]:
    if path is None:
        return data
    with open(os.fspath(path), "wb") as f:
        f.write(data)
    return None


def _format(format: Optional[str], path) -> str:
    if format is None and path is not None:
        format = os.path.splitext(os.fspath(path))[1].lstrip(".").lower()
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
) -> Optional[bytes]:
    """Renders a mesh as vector graphics: ``format`` ``"svg"``, ``"pdf"``
    or ``"tex"`` (a TikZ picture), by default from ``path``'s extension,
    else SVG. Returns the file's bytes, or writes them to ``path`` and
    returns ``None``. The polygons are split and ordered by the NNS sort,
    so the picture is exact; ``size`` is its size in user units (pixels).
    The other arguments are those of :func:`render`.
    """
    fmt = _format(format if format is not None or path is not None else "svg", path)
    scene = _mesh_scene(
        vertices, faces, colors, face_colors, vertex_colors, material, camera, lights,
        size, background,
    )
    return _write_or_return(scene.render_vector(fmt, None, bool(shadows)), path)


class Scene:
    """A scene in plytrace's scene descriptor language (``.des``).

    ``Scene.from_file(path)`` reads a file; ``Scene.from_string(text,
    directory=".")`` reads its text (object files named in it are looked
    up in ``directory``). A scene shows itself in Jupyter (as PNG or SVG).
    Errors in the scene raise :class:`SceneError` with the file, line and
    column.
    """

    #: Largest side of the picture Jupyter shows, in pixels.
    repr_size: int = 512

    def __init__(self, native: _NativeScene):
        self._native = native

    @classmethod
    def from_file(cls, path: Union[str, os.PathLike]) -> "Scene":
        """Reads a scene descriptor file (its ``run`` commands are not
        acted on: call :meth:`render`)."""
        return cls(_NativeScene.from_file(os.fspath(path)))

    @classmethod
    def from_string(cls, text: str, directory: Union[str, os.PathLike] = ".") -> "Scene":
        """Reads a scene from the text of a scene descriptor file."""
        if not isinstance(text, str):
            raise ValueError(f"text must be a str, not {type(text).__name__}")
        return cls(_NativeScene.from_text(text, os.fspath(directory)))

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
    ) -> np.ndarray:
        """Renders to an ``(height, width, 3)`` uint8 array, at ``size`` or
        the scene's own resolution."""
        return self._native.render(
            None if size is None else _size(size), bool(antialias), bool(shadows)
        )

    def render_vector(
        self,
        format: Optional[str] = None,
        path: Union[str, os.PathLike, None] = None,
        *,
        size: Optional[Tuple[int, int]] = None,
        shadows: bool = True,
    ) -> Optional[bytes]:
        """Renders as SVG, PDF or TikZ (``format`` ``"svg"``, ``"pdf"``,
        ``"tex"``; by default from ``path``'s extension, else SVG). Returns
        the bytes, or writes ``path`` and returns ``None``."""
        fmt = _format(format if format is not None or path is not None else "svg", path)
        data = self._native.render_vector(
            fmt, None if size is None else _size(size), bool(shadows)
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
