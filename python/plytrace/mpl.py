"""Correct hidden surfaces in matplotlib's 3-D plots.

matplotlib's ``mplot3d`` paints each polygon of a 3-D collection as a
whole, ordered by one depth per polygon (and each collection as a whole
among the others), so interpenetrating surfaces, ``bar3d`` cities and
surfaces crossing lines come out wrong. With this module, at draw time
the 3-D artists of an axes (the polygons of ``plot_surface``,
``plot_trisurf``, ``bar3d``, ``voxels``, ``Poly3DCollection`` and 3-D
patches, the lines of ``plot``, ``plot_wireframe``, ``quiver`` and
``Line3DCollection``, ``scatter`` markers and 3-D text) are painted in
one order: plytrace splits the polygons and orders their pieces with the
Newell-Newell-Sancha sort in the axes' own projection (``ax.get_proj()``),
cuts lines where an opaque polygon hides them, and paints each line part,
marker and label just before the first piece in front of it. Every
backend (SVG, PDF, PGF, PNG) then draws the correct picture; the axes,
ticks, labels, colorbars and the colours matplotlib computed (colormaps,
shading) are unchanged::

    import plytrace.mpl
    plytrace.mpl.fix(ax)                     # this axes, from now on
    plytrace.mpl.savefig(fig, "plot.svg")    # or for one save
    with plytrace.mpl.fixed(fig):            # or within a block
        fig.savefig("plot.pdf")

A polygon that is not planar (the quads of ``plot_surface``) is taken as
the fan of triangles from its first vertex. Translucent and unfilled
polygons hide nothing: what is behind them is painted under them. Each
artist draws its own pieces (its gid, url, hatch, clip path and
rasterization are kept), and keeps matplotlib's 2-D projection between
draws, so ``get_paths``, ``contains`` and picking work. With
``ax.computed_zorder = False`` the artists' zorders order them, and the
bridge orders only the artists of one zorder among themselves.
"""

from __future__ import annotations

import contextlib
import io
import math
import numbers
import os
import types
from typing import Dict, Iterator, List, Tuple, Type, Union

import numpy as np
from matplotlib import artist as martist
from matplotlib import rcParams
from matplotlib.figure import FigureBase
from mpl_toolkits.mplot3d.axes3d import Axes3D

from . import _mpl_level
from ._native import write_file

__all__ = ["fix", "unfix", "is_fixed", "fixed", "savefig", "SEAM_WIDTH"]

#: Default width, in points, that closes seams (see :func:`fix`).
SEAM_WIDTH = 0.3


def _axes(target) -> List[Axes3D]:
    if isinstance(target, Axes3D):
        return [target]
    if isinstance(target, FigureBase):
        found = [ax for ax in getattr(target, "axes") if isinstance(ax, Axes3D)]
        for sub in getattr(target, "subfigs", []):
            found += [ax for ax in _axes(sub) if ax not in found]
        return found
    raise TypeError(
        f"expected a matplotlib Figure, SubFigure or 3-D Axes, not {type(target).__name__}"
    )


class _Fixed:
    """Mixed into an axes' class by :func:`fix`: its draw goes through the
    bridge. A fixed axes pickles and copies as one (its class is made
    again from the base class when it is loaded)."""

    def draw(self, renderer) -> None:
        _draw(self, renderer)

    draw._supports_rasterization = True  # type: ignore[attr-defined]

    def __reduce_ex__(self, protocol):
        return (_remade, (_base(type(self)),), self.__getstate__())


_CLASSES: Dict[type, type] = {}


def _fixed_class(base: type) -> type:
    """The fixed class of ``base`` (one per base class)."""
    cls = _CLASSES.get(base)
    if cls is None:
        # Named as its base (its repr is the axes' own).
        cls = type(base.__name__, (_Fixed, base),
                   {"__module__": __name__, "__qualname__": base.__qualname__})
        _CLASSES[base] = cls
    return cls


def _base(cls: type) -> type:
    return cls.__bases__[1]


def _remade(base: type) -> Axes3D:
    """An empty fixed axes of ``base``, for unpickling and copying."""
    return object.__new__(_fixed_class(base))


def fix(target: Union[Axes3D, FigureBase], *, seam_width: float = SEAM_WIDTH) -> None:
    """Draws ``target`` (a 3-D axes, or every 3-D axes of a figure or
    subfigure) with plytrace's hidden-surface removal from now on.

    ``seam_width``: each opaque polygon without an edge of its own is
    grown by half this width (in points) on every side, which closes the
    hairline seams that anti-aliasing leaves between adjacent polygons
    (and between the pieces of a split one); 0 leaves them.
    """
    seam_width = _seam_width(seam_width)
    for ax in _axes(target):
        if not is_fixed(ax):
            ax.__class__ = _fixed_class(type(ax))
        ax._plytrace_seam_width = seam_width


def _seam_width(value) -> float:
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
        raise TypeError(f"seam_width must be a number, not {type(value).__name__}")
    w = float(value)
    if not (math.isfinite(w) and w >= 0):
        raise ValueError(f"seam_width must be a finite number, 0 or more, not {w}")
    return w


def unfix(target: Union[Axes3D, FigureBase]) -> None:
    """Undoes :func:`fix`."""
    for ax in _axes(target):
        if is_fixed(ax):
            ax.__class__ = _base(type(ax))
            ax.__dict__.pop("_plytrace_seam_width", None)


def is_fixed(ax: Axes3D) -> bool:
    """Whether :func:`fix` is in force for ``ax``."""
    return isinstance(ax, _Fixed)


@contextlib.contextmanager
def fixed(target: Union[Axes3D, FigureBase], *, seam_width: float = SEAM_WIDTH) -> Iterator[None]:
    """A context in which ``target`` (a 3-D axes, a figure or a subfigure)
    is drawn with plytrace's hidden-surface removal (``seam_width`` as for
    :func:`fix`)."""
    _seam_width(seam_width)
    axes = [ax for ax in _axes(target) if not is_fixed(ax)]
    for ax in axes:
        fix(ax, seam_width=seam_width)
    try:
        yield
    finally:
        for ax in axes:
            unfix(ax)


def savefig(fig, fname, *, seam_width: float = SEAM_WIDTH, **kwargs) -> None:
    """``fig.savefig(fname, **kwargs)`` with every 3-D axes of ``fig``
    drawn with plytrace's hidden-surface removal (``seam_width`` as for
    :func:`fix`). A file named by ``fname`` is written whole or not at
    all (through plytrace's atomic writer: an earlier file survives a
    failed write); a file object is written as matplotlib writes it."""
    with fixed(fig, seam_width=seam_width):
        if not isinstance(fname, (str, os.PathLike)):
            fig.savefig(fname, **kwargs)
            return
        # matplotlib's choice of format and name: the format given, else
        # the extension, else savefig.format added as the extension.
        path = os.fsdecode(os.fspath(fname))
        fmt = kwargs.pop("format", None)
        if fmt is None:
            fmt = os.path.splitext(path)[1][1:].lower()
            if not fmt:
                fmt = rcParams["savefig.format"]
                path = f"{path}.{fmt}"
        buf = io.BytesIO()
        fig.savefig(buf, format=fmt, **kwargs)
        write_file(path, buf.getvalue())


def _draw(ax: Axes3D, renderer) -> None:
    """The axes' own draw, with its 3-D artists drawn by levels."""
    installed: List[object] = []
    try:
        for level in _levels(ax, renderer):
            for m in level.members:
                m.draw = types.MethodType(_member_draw(level), m)
                if hasattr(m, "do_3d_projection"):
                    m.do_3d_projection = types.MethodType(_member_projection(level), m)
                installed.append(m)
        super(_Fixed, ax).draw(renderer)  # type: ignore[misc]
    finally:
        for m in installed:
            m.__dict__.pop("draw", None)
            m.__dict__.pop("do_3d_projection", None)


def _member_draw(level):
    return lambda artist, renderer: level.draw_member(artist, renderer)


def _member_projection(level):
    def project(artist):
        depth = type(artist).do_3d_projection(artist)
        level.projected(artist)
        return depth
    return project


def _levels(ax: Axes3D, renderer) -> List["_mpl_level.Level"]:
    """The axes' 3-D artists in levels: one, or with ``computed_zorder``
    off one per zorder; a level without polygons is left to matplotlib."""
    members = [a for a in ax.get_children() if a.get_visible() and _mpl_level.member(a)]
    if getattr(ax, "computed_zorder", True):
        groups = [members]
    else:
        by: Dict[float, list] = {}
        for a in members:
            by.setdefault(a.get_zorder(), []).append(a)
        groups = list(by.values())
    return [_mpl_level.Level(ax, g, renderer) for g in groups
            if any(isinstance(a, _mpl_level.POLYGONS) for a in g)]
