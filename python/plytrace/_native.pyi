"""Type stubs of ``plytrace._native``, the compiled part of the package
(the renderer's library API). Use the documented functions of
``plytrace`` and ``plytrace.mpl``, which check their arguments; these
take arrays already checked and converted."""

from os import PathLike
from typing import Dict, Optional, Sequence, Tuple, Union, final

import numpy as np
import numpy.typing as npt

__version__: str
MAX_IMAGE_SIDE: int
MAX_IMAGE_PIXELS: int
__all__ = [
    "MAX_IMAGE_PIXELS",
    "MAX_IMAGE_SIDE",
    "NativeScene",
    "Projection",
    "SceneError",
    "__version__",
    "check_mesh",
    "default_budgets",
    "write_file",
]

_Budgets = Optional[Dict[str, int]]

def default_budgets() -> Dict[str, int]: ...
def check_mesh(
    name: str, vertices: int, faces: int, corners: int, budgets: _Budgets = None
) -> None: ...
def write_file(path: Union[str, PathLike[str]], data: bytes) -> None: ...

class SceneError(ValueError):
    """An error in a scene description, with its place."""

    file: str
    """The file (``<text>`` for a scene read from a string)."""
    line: int
    """1-based line, 0 when not known."""
    column: int
    """1-based column, 0 when not known."""
    message: str
    """What is wrong, without the place."""

_Vec3 = Tuple[float, float, float]

@final
class NativeScene:
    @staticmethod
    def new(
        eye: _Vec3,
        target: _Vec3,
        up: _Vec3,
        fovy: float,
        near: float,
        far: float,
        ortho: Optional[Tuple[float, float, float, float]],
        width: int,
        height: int,
    ) -> NativeScene: ...
    @staticmethod
    def from_file(path: Union[str, PathLike[str]], budgets: _Budgets = None) -> NativeScene: ...
    @staticmethod
    def from_text(
        text: str, dir: Union[str, PathLike[str]], budgets: _Budgets = None
    ) -> NativeScene: ...
    def set_budgets(self, budgets: Dict[str, int]) -> None: ...
    def add_light(self, position: _Vec3, color: _Vec3, range: float, shadows: bool) -> None: ...
    def add_mesh(
        self,
        name: str,
        vertices: npt.NDArray[np.float64],
        indices: npt.NDArray[np.uint32],
        sizes: npt.NDArray[np.uint32],
        face_colors: Optional[npt.NDArray[np.float64]],
        vertex_colors: Optional[npt.NDArray[np.float64]],
        color: _Vec3,
        coefficients: Sequence[float],
        two_sided: bool,
        smooth: bool,
    ) -> None: ...
    def set_background(self, rgb: _Vec3) -> None: ...
    def set_ambient(self, rgb: _Vec3) -> None: ...
    def size(self) -> Tuple[int, int]: ...
    def render(
        self,
        size: Optional[Tuple[int, int]],
        antialias: bool,
        shadows: bool,
        budgets: _Budgets = None,
    ) -> npt.NDArray[np.uint8]: ...
    def render_png(
        self,
        size: Optional[Tuple[int, int]],
        antialias: bool,
        shadows: bool,
        budgets: _Budgets = None,
    ) -> bytes: ...
    def render_vector(
        self,
        format: str,
        size: Optional[Tuple[int, int]],
        shadows: bool,
        budgets: _Budgets = None,
    ) -> bytes: ...

_Paths = Tuple[npt.NDArray[np.float64], npt.NDArray[np.uint8], npt.NDArray[np.int64]]

@final
class Projection:
    def __new__(
        cls,
        points: npt.NDArray[np.float64],
        sizes: npt.NDArray[np.int64],
        matrix: npt.NDArray[np.float64],
        open: Optional[npt.NDArray[np.bool_]] = None,
    ) -> Projection: ...
    def paint_order(
        self,
        grow: Optional[Tuple[float, float]] = None,
        grown: Optional[npt.NDArray[np.bool_]] = None,
        keys: Optional[npt.NDArray[np.uint32]] = None,
    ) -> Tuple[
        npt.NDArray[np.int64], npt.NDArray[np.bool_], _Paths, _Paths, int, Optional[str]
    ]: ...
    def layered(
        self,
        grow: Optional[Tuple[float, float]],
        grown: npt.NDArray[np.bool_],
        keys: npt.NDArray[np.uint32],
        opaque: npt.NDArray[np.bool_],
        points: npt.NDArray[np.float64],
        sizes: npt.NDArray[np.int64],
        anchors: npt.NDArray[np.float64],
    ) -> Tuple[
        Tuple[
            npt.NDArray[np.int64], npt.NDArray[np.bool_], _Paths, _Paths, int, Optional[str]
        ],
        Tuple[
            npt.NDArray[np.float64],
            npt.NDArray[np.int64],
            npt.NDArray[np.int64],
            npt.NDArray[np.int64],
        ],
        npt.NDArray[np.int64],
    ]: ...
    def visible_polylines(
        self, points: npt.NDArray[np.float64], sizes: npt.NDArray[np.int64]
    ) -> Tuple[npt.NDArray[np.float64], npt.NDArray[np.int64], npt.NDArray[np.bool_]]: ...
