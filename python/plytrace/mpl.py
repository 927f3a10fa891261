"""Correct hidden surfaces in matplotlib's 3-D plots.

matplotlib's ``mplot3d`` paints each polygon of a 3-D collection as a
whole, ordered by one depth per polygon (and each collection as a whole
among the others), so interpenetrating surfaces, ``bar3d`` cities and
surfaces crossing lines come out wrong. With this module, at draw time
the 3-D polygon collections of an axes (``plot_surface``,
``plot_trisurf``, ``bar3d``, ``voxels``, ``add_collection3d`` of a
``Poly3DCollection``) are replaced by 2-D polygons that plytrace splits
and orders with the Newell-Newell-Sancha sort in the axes' own projection
(``ax.get_proj()``), and 3-D lines (``plot``, ``plot_wireframe``,
``Line3DCollection``) are cut where a surface hides them. Every backend
(SVG, PDF, PGF, PNG) then draws the correct picture; the axes, ticks,
labels, colorbars and the colours matplotlib computed (colormaps,
shading) are unchanged::

    import plytrace.mpl
    plytrace.mpl.fix(ax)                     # this axes, from now on
    plytrace.mpl.savefig(fig, "plot.svg")    # or for one save
    with plytrace.mpl.fixed(fig):            # or within a block
        fig.savefig("plot.pdf")

A polygon that is not planar (the quads of ``plot_surface``) is taken as
the fan of triangles from its first vertex. Polygons with a vertex that is
not finite (or not valid on a log axis) are left out, as are lines'
points that are not. Scatter markers and 3-D patches keep matplotlib's
order.
"""

from __future__ import annotations

import contextlib
import io
import math
import numbers
import os
import types
import warnings
from typing import Dict, Iterator, List, Optional, Tuple, Union

import numpy as np
from matplotlib import collections as mcoll
from matplotlib import rcParams
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.path import Path
from mpl_toolkits.mplot3d import art3d, proj3d
from mpl_toolkits.mplot3d.axes3d import Axes3D

from ._native import Projection, write_file

__all__ = ["fix", "unfix", "is_fixed", "fixed", "savefig"]

_TRANSPARENT = np.zeros(4)

#: Per source polygon: fill and edge colours, line widths, line styles,
#: anti-aliasing.
_Styles = Tuple[np.ndarray, np.ndarray, np.ndarray, List[object], np.ndarray]


def _axes(target) -> List[Axes3D]:
    if isinstance(target, Axes3D):
        return [target]
    if isinstance(target, Figure):
        return [ax for ax in target.get_axes() if isinstance(ax, Axes3D)]
    raise TypeError(
        f"expected a matplotlib Figure or 3-D Axes, not {type(target).__name__}"
    )


#: Default width, in points, that closes seams (see :func:`fix`).
SEAM_WIDTH = 0.3


def fix(target: Union[Axes3D, Figure], *, seam_width: float = SEAM_WIDTH) -> None:
    """Draws ``target`` (a 3-D axes, or every 3-D axes of a figure) with
    plytrace's hidden-surface removal from now on.

    ``seam_width``: each opaque polygon without an edge of its own is
    grown by half this width (in points) on every side, which closes the
    hairline seams that anti-aliasing leaves between adjacent polygons
    (and between the pieces of a split one); 0 leaves them.
    """
    seam_width = _seam_width(seam_width)
    for ax in _axes(target):
        ax.draw = types.MethodType(_draw, ax)
        ax._plytrace_seam_width = seam_width


def _seam_width(value) -> float:
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
        raise TypeError(f"seam_width must be a number, not {type(value).__name__}")
    w = float(value)
    if not (math.isfinite(w) and w >= 0):
        raise ValueError(f"seam_width must be a finite number, 0 or more, not {w}")
    return w


def unfix(target: Union[Axes3D, Figure]) -> None:
    """Undoes :func:`fix`."""
    for ax in _axes(target):
        if is_fixed(ax):
            del ax.draw
            ax.__dict__.pop("_plytrace_seam_width", None)


def is_fixed(ax: Axes3D) -> bool:
    """Whether :func:`fix` is in force for ``ax``."""
    d = ax.__dict__.get("draw")
    return isinstance(d, types.MethodType) and d.__func__ is _draw


@contextlib.contextmanager
def fixed(target: Union[Axes3D, Figure], *, seam_width: float = SEAM_WIDTH) -> Iterator[None]:
    """A context in which ``target`` (a 3-D axes or a figure) is drawn
    with plytrace's hidden-surface removal (``seam_width`` as for
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


def savefig(fig: Figure, fname, *, seam_width: float = SEAM_WIDTH, **kwargs) -> None:
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
    """The axes' draw, with its 3-D polygons and lines replaced for the
    time of the draw."""
    drawing = _Drawing(ax)
    drawing.install()
    try:
        type(ax).draw(ax, renderer)
    finally:
        drawing.uninstall()


def _scaled(ax: Axes3D, xyz: np.ndarray) -> np.ndarray:
    """Data coordinates through the axes' scales (log, symlog...), which
    matplotlib applies before its projection."""
    apply = getattr(proj3d, "_apply_scale_transforms", None)
    if apply is None or len(xyz) == 0:
        return xyz
    with np.errstate(all="ignore"):
        xs, ys, zs = apply(xyz[:, 0], xyz[:, 1], xyz[:, 2], ax)
    return np.column_stack([np.ma.getdata(xs), np.ma.getdata(ys), np.ma.getdata(zs)])


def _invalid(ax: Axes3D, xs, ys, zs, clip: bool):
    """Points matplotlib leaves out: invalid on the axis scale, outside
    the view limits when the artist clips to them, or not finite."""
    bad = ~(np.isfinite(xs) & np.isfinite(ys) & np.isfinite(zs))
    with np.errstate(all="ignore"):
        scale = getattr(art3d, "_scale_invalid_mask", None)
        if scale is not None:
            bad |= scale(xs, ys, zs, ax)
        if clip:
            bad |= art3d._viewlim_mask(xs, ys, zs, ax)
    return bad


def _polygons(ax: Axes3D, col):
    """The collection's polygons as points and sizes, and the indices of
    the polygons drawn."""
    faces = getattr(col, "_faces", None)
    if faces is not None:
        faces = np.asarray(faces, dtype=float)
        n, m = faces.shape[:2]
        padding = np.broadcast_to(np.asarray(col._invalid_vertices, dtype=bool), (n, m))
    else:  # matplotlib before 3.9: one array of points and slices
        vec = np.asarray(col._vec)
        slices = col._segslices
        n = len(slices)
        m = max((s.stop - s.start for s in slices), default=0)
        faces = np.zeros((n, m, 3))
        padding = np.ones((n, m), dtype=bool)
        for i, s in enumerate(slices):
            k = s.stop - s.start
            faces[i, :k] = vec[:3, s].T
            padding[i, :k] = False
    if n == 0:
        return np.zeros((0, 3)), np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int64)
    valid = ~padding
    bad = _invalid(
        ax, faces[..., 0], faces[..., 1], faces[..., 2], getattr(col, "_axlim_clip", False)
    )
    keep = ~(bad & valid).any(axis=1) & (valid.sum(axis=1) >= 3)
    kept = np.flatnonzero(keep)
    points = faces[kept][valid[kept]]
    sizes = valid[kept].sum(axis=1).astype(np.int64)
    return _scaled(ax, points), sizes, kept


def _colors_and_depth(ax: Axes3D, col, points: np.ndarray) -> float:
    """What matplotlib's ``do_3d_projection`` does that the bridge keeps:
    the colour mapping brought up to date, and the depth matplotlib sorts
    collections by (returned). Falls back on ``do_3d_projection`` itself
    where this matplotlib lacks what it reads."""
    try:
        if col._A is not None:
            col.update_scalarmappable()
            if col._face_is_mapped:
                col._facecolor3d = col._facecolors
            if col._edge_is_mapped:
                col._edgecolor3d = col._edgecolors
        zpos = col._sort_zpos
    except AttributeError:
        return type(col).do_3d_projection(col)
    m = np.asarray(ax.M, dtype=float)
    if zpos is not None:
        h = m @ np.array([0.0, 0.0, zpos, 1.0])
        return float(h[2] / h[3])
    if len(points) == 0:
        return np.nan
    h = points @ m[:, :3].T + m[:, 3]
    return float(np.min(h[:, 2] / h[:, 3]))


def _per_face(colors, n: int) -> np.ndarray:
    """RGBA per face from a collection's colour array (one, one per face,
    or none: transparent)."""
    c = np.asarray(colors, dtype=float).reshape(-1, 4) if len(colors) else np.zeros((0, 4))
    if len(c) == n:
        return c
    if len(c) == 0:
        return np.zeros((n, 4))
    return np.repeat(c[:1], n, axis=0) if len(c) == 1 else np.resize(c, (n, 4))


def _cycle(values, n: int) -> list:
    values = list(values) if len(values) else [None]
    return [values[i % len(values)] for i in range(n)]


class _Drawing:
    """One draw of a fixed axes: the instance-level overrides that replace
    its 3-D collections' projection and drawing, and what they compute."""

    def __init__(self, ax: Axes3D):
        self.ax = ax
        children = ax.get_children()
        self.polys = [
            c for c in children
            if isinstance(c, art3d.Poly3DCollection) and c.get_visible()
        ]
        self.lines = [
            c for c in children
            if isinstance(c, (art3d.Line3D, art3d.Line3DCollection)) and c.get_visible()
        ]
        self.overridden: List[Tuple[object, str]] = []
        self.depths: Dict[int, float] = {}
        self.projection: Optional[Projection] = None
        self.styles: Optional[_Styles] = None
        self.drawn = False

    def install(self) -> None:
        if not self.polys:
            return  # nothing can hide anything
        for c in self.polys:
            self._override(c, "do_3d_projection", self._project_polygons)
            self._override(c, "draw", self._draw_polygons)
        for c in self.lines:
            if isinstance(c, art3d.Line3DCollection):
                self._override(c, "do_3d_projection", self._project_line_collection)
            self._override(c, "draw", lambda artist, renderer: None)

    def _override(self, artist, name: str, method) -> None:
        setattr(artist, name, types.MethodType(lambda a, *args: method(a, *args), artist))
        self.overridden.append((artist, name))

    def uninstall(self) -> None:
        for artist, name in self.overridden:
            artist.__dict__.pop(name, None)
        self.overridden.clear()

    # Polygons

    def _project_polygons(self, col):
        if self.projection is None:
            self._compute()
        return self.depths.get(id(col), np.nan)

    def _compute(self) -> None:
        ax = self.ax
        points: List[np.ndarray] = []
        sizes: List[np.ndarray] = []
        fill: List[np.ndarray] = []
        edge: List[np.ndarray] = []
        widths: List[np.ndarray] = []
        styles: List[object] = []
        antialiased: List[np.ndarray] = []
        for c in self.polys:
            p, s, kept = _polygons(ax, c)
            self.depths[id(c)] = _colors_and_depth(ax, c, p)
            n = len(c._faces) if hasattr(c, "_faces") else len(c._segslices)
            points.append(p)
            sizes.append(s)
            fill.append(_per_face(c._facecolor3d, n)[kept])
            edge.append(_per_face(c._edgecolor3d, n)[kept])
            widths.append(np.asarray(_cycle(c.get_linewidth(), n), dtype=float)[kept])
            ls = _cycle(c.get_linestyle(), n)
            styles.extend(ls[i] for i in kept)
            antialiased.append(np.asarray(_cycle(c.get_antialiased(), n), dtype=bool)[kept])
        self.projection = Projection(
            np.ascontiguousarray(np.concatenate(points), dtype=float),
            np.ascontiguousarray(np.concatenate(sizes), dtype=np.int64),
            np.ascontiguousarray(ax.M, dtype=float),
        )
        self.styles = (
            np.concatenate(fill),
            np.concatenate(edge),
            np.concatenate(widths),
            styles,
            np.concatenate(antialiased),
        )

    def _paint(self, renderer) -> mcoll.PathCollection:
        """The polygons' pieces in paint order, as one 2-D collection."""
        assert self.projection is not None and self.styles is not None
        fill, edge, widths, styles, antialiased = self.styles
        stroked = (edge[:, 3] > 0) & (widths > 0)
        # Opaque faces without edges of their own are grown by half the
        # seam width, in display units, on every side.
        seam = getattr(self.ax, "_plytrace_seam_width", SEAM_WIDTH)
        grown = ~stroked & (fill[:, 3] >= 1.0)
        grow = None
        if seam > 0 and grown.any():
            half = seam / 2 * renderer.points_to_pixels(1.0)
            m = self.ax.transData.get_affine().get_matrix()
            sx, sy = np.hypot(m[0, 0], m[1, 0]), np.hypot(m[0, 1], m[1, 1])
            if sx > 0 and sy > 0:
                grow = (half / sx, half / sy)
        # Opaque faces without edges of one colour are filled together
        # where the order allows: fewer paths, and no seams between them.
        style = np.column_stack([fill, antialiased])
        _, same = np.unique(style, axis=0, return_inverse=True)
        same = same.reshape(-1)
        keys = np.where(grown, same, same.max(initial=0) + 1 + np.arange(len(fill)))
        sources, whole, fills, edges, _splits, warning = self.projection.paint_order(
            grow, np.ascontiguousarray(grown), np.ascontiguousarray(keys, dtype=np.uint32)
        )
        if warning:
            warnings.warn(f"plytrace.mpl: {warning}", RuntimeWarning, stacklevel=2)
        return self._collection(
            sources, whole, fills, edges, fill, edge, widths, styles, antialiased
        )

    def _collection(self, sources, whole, fills, edges, fill, edge, widths, styles, aa):
        fv, fcodes, fstarts = fills
        ev, ecodes, estarts = edges
        stroked = (edge[:, 3] > 0) & (widths > 0)
        # Per patch: one path. Pieces of a split polygon with edges of its
        # own get no edge; a path of the edges on its outline follows.
        sources = np.asarray(sources)
        split = stroked[sources] & ~np.asarray(whole, dtype=bool)
        paths = [Path(fv[a:b], fcodes[a:b]) for a, b in zip(fstarts[:-1], fstarts[1:])]
        order = np.arange(len(sources))
        face = fill[sources]
        edgec = np.where(split[:, None], _TRANSPARENT, edge[sources])
        src = sources
        if split.any():
            extra = [g for g in np.flatnonzero(split) if estarts[g + 1] > estarts[g]]
            for g in extra:
                paths.append(Path(ev[estarts[g]:estarts[g + 1]], ecodes[estarts[g]:estarts[g + 1]]))
            extra = np.asarray(extra, dtype=int)
            # Each edge path right after its patch.
            keys = np.concatenate([order * 2.0, extra * 2.0 + 1])
            order = np.argsort(keys, kind="stable")
            paths = [paths[k] for k in order]
            face = np.concatenate([face, np.zeros((len(extra), 4))])[order]
            edgec = np.concatenate([edgec, edge[sources[extra]]])[order]
            src = np.concatenate([sources, sources[extra]])[order]
        lw = widths[src]
        anti = aa[src]
        ls = [styles[i] for i in src]
        # One value for all where they agree: the backends then set it
        # once, not per path.
        if len(src) and (edgec[:, 3] == 0).all():
            edgec, lw = "none", lw[:1]
        elif len(src) and (edgec == edgec[0]).all():
            edgec = edgec[:1]
        if len(lw) and (lw == lw[0]).all():
            lw = lw[:1]
        if len(anti) and (anti == anti[0]).all():
            anti = anti[:1]
        if ls and all(v == ls[0] for v in ls):
            ls = ls[:1]
        return mcoll.PathCollection(
            paths,
            facecolors=face.reshape(-1, 4),
            edgecolors=edgec if isinstance(edgec, str) else edgec.reshape(-1, 4),
            linewidths=lw if len(lw) else [0.0],
            linestyles=ls or ["solid"],
            antialiaseds=anti if len(anti) else [True],
            joinstyle="round",
        )

    def _draw_polygons(self, col, renderer) -> None:
        if self.drawn:
            return
        self.drawn = True
        if self.projection is None:
            self._compute()
        combined = self._paint(renderer)
        combined.set_figure(self.ax.figure)
        combined.axes = self.ax
        combined.set_transform(self.ax.transData)
        combined.set_clip_on(col.get_clip_on())
        combined.set_clip_box(col.get_clip_box())
        clip = col.get_clip_path()
        if clip is not None:
            combined.set_clip_path(clip)
        combined.set_rasterized(col.get_rasterized())
        combined.set_gid(col.get_gid())
        combined.set_zorder(col.get_zorder())
        combined.draw(renderer)
        # The lines' visible pieces, over every polygon.
        for line in sorted(self.lines, key=lambda a: a.get_zorder()):
            if isinstance(line, art3d.Line3DCollection):
                mcoll.LineCollection.draw(line, renderer)
            else:
                self._draw_line(line, renderer)

    # Lines

    def _visible(self, polylines):
        """The visible parts of 3-D polylines (arrays of points, with
        points that are not finite breaking them): per polyline, its 2-D
        points with NaN rows between pieces, and per point whether it is
        seen."""
        pieces, owner, seen_at = [], [], []
        for k, pts in enumerate(polylines):
            pts = np.asarray(np.ma.filled(np.ma.asarray(pts, dtype=float), np.nan))
            if pts.ndim != 2 or len(pts) == 0:
                continue
            bad = _invalid(self.ax, pts[:, 0], pts[:, 1], pts[:, 2], False)
            runs = np.split(np.arange(len(pts)), np.flatnonzero(np.diff(bad.astype(int))) + 1)
            for run in runs:
                if not bad[run[0]]:
                    pieces.append(_scaled(self.ax, pts[run]))
                    owner.append(k)
                    seen_at.append(run)
        out = [np.zeros((0, 2)) for _ in polylines]
        seen = [np.zeros(len(np.atleast_2d(p)), dtype=bool) for p in polylines]
        if not pieces:
            return out, seen
        xy, starts, visible = self.projection.visible_polylines(
            np.ascontiguousarray(np.concatenate(pieces), dtype=float),
            np.array([len(p) for p in pieces], dtype=np.int64),
        )
        nan = np.full((1, 2), np.nan)
        at = 0
        for i, k in enumerate(owner):
            part = xy[starts[i]:starts[i + 1]]
            if len(part):
                out[k] = np.concatenate([out[k], nan, part]) if len(out[k]) else part
            seen[k][seen_at[i]] = visible[at:at + len(seen_at[i])]
            at += len(seen_at[i])
        return out, seen

    def _draw_line(self, line: art3d.Line3D, renderer) -> None:
        xs, ys, zs = (np.asarray(v, dtype=float).ravel() for v in line.get_data_3d())
        n = len(xs)
        xs, ys, zs = (np.broadcast_to(v, (n,)) for v in (xs, ys, zs))
        (xy,), (seen,) = self._visible([np.column_stack([xs, ys, zs])])
        marker = line.get_marker()
        has_markers = marker not in (None, "None", "none", "", " ")
        if not has_markers or line.get_markevery() is not None:
            Line2D.set_data(line, xy[:, 0], xy[:, 1])
            Line2D.draw(line, renderer)
            return
        # The line without markers, then the markers of the points seen.
        linestyle = line.get_linestyle()
        try:
            line.set_marker("None")
            Line2D.set_data(line, xy[:, 0], xy[:, 1])
            Line2D.draw(line, renderer)
            line.set_marker(marker)
            line.set_linestyle("None")
            pts = _scaled(self.ax, np.column_stack([xs, ys, zs])[seen])
            if len(pts):
                h = np.column_stack([pts, np.ones(len(pts))]) @ np.asarray(self.ax.M).T
                Line2D.set_data(line, h[:, 0] / h[:, 3], h[:, 1] / h[:, 3])
                Line2D.draw(line, renderer)
        finally:
            line.set_marker(marker)
            line.set_linestyle(linestyle)
            line.stale = False

    def _project_line_collection(self, col):
        depth = type(col).do_3d_projection(col)
        if self.projection is None:
            self._compute()
        segments = col._segments3d
        polylines = [np.asarray(np.ma.filled(np.ma.asarray(s, dtype=float), np.nan)) for s in segments]
        visible, _ = self._visible(polylines)
        mcoll.LineCollection.set_segments(col, visible)
        return depth
