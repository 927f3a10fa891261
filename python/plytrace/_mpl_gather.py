"""What ``plytrace.mpl`` reads from an axes' 3-D artists at draw time:
polygons (``Poly3DCollection``, ``Patch3D``) with their styles, polylines
(``Line3D``, ``Line3DCollection``) and anchor points (markers of lines and
of ``scatter``, 3-D text), in the axes' scaled data coordinates, with the
points matplotlib leaves out (not finite, invalid on a log axis, outside
the view limits under ``axlim_clip``) left out too."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import List, Optional, Tuple

import numpy as np
from matplotlib.path import Path
from mpl_toolkits.mplot3d import art3d, proj3d


def scaled(ax, xyz: np.ndarray) -> np.ndarray:
    """Data coordinates through the axes' scales (log, symlog...), which
    matplotlib applies before its projection."""
    apply = getattr(proj3d, "_apply_scale_transforms", None)
    if apply is None or len(xyz) == 0:
        return xyz
    with np.errstate(all="ignore"):
        xs, ys, zs = apply(xyz[:, 0], xyz[:, 1], xyz[:, 2], ax)
    return np.column_stack([np.ma.getdata(xs), np.ma.getdata(ys), np.ma.getdata(zs)])


def invalid(ax, xs, ys, zs, clip: bool) -> np.ndarray:
    """Points matplotlib leaves out: not finite, invalid on the axis
    scale, or outside the view limits when the artist clips to them."""
    xs, ys, zs = (np.asarray(np.ma.filled(np.ma.asarray(v, dtype=float), np.nan)) for v in
                  (xs, ys, zs))
    bad = ~(np.isfinite(xs) & np.isfinite(ys) & np.isfinite(zs))
    with np.errstate(all="ignore"):
        scale = getattr(art3d, "_scale_invalid_mask", None)
        if scale is not None:
            bad |= np.asarray(scale(xs, ys, zs, ax), dtype=bool)
        if clip:
            bad |= np.asarray(art3d._viewlim_mask(xs, ys, zs, ax), dtype=bool)
    return bad


def cycled(values, n: int) -> np.ndarray:
    """Per item of n, a collection's property given once, per item, or
    cycled (as matplotlib cycles them)."""
    a = np.asarray(values)
    if len(a) == 0:
        return a
    return a[np.arange(n) % len(a)]


def per_face(colors, n: int) -> np.ndarray:
    """RGBA per face from a colour array (one, one per face, or none:
    transparent)."""
    c = np.asarray(colors, dtype=float).reshape(-1, 4) if len(colors) else np.zeros((0, 4))
    if len(c) == 0:
        return np.zeros((n, 4))
    return c if len(c) == n else c[np.arange(n) % len(c)]


@dataclass
class Polygons:
    """The polygons of one artist: points (scaled) and sizes, the index of
    each among the artist's faces, and their styles."""

    points: np.ndarray
    sizes: np.ndarray
    kept: np.ndarray
    fill: np.ndarray
    edge: np.ndarray
    widths: np.ndarray
    open: np.ndarray


def collection_polygons(ax, col) -> Optional[Polygons]:
    """A Poly3DCollection's polygons; None when it has faces this bridge
    cannot take (several subpaths: holes), which matplotlib then draws."""
    faces, padding = _faces(col)
    n = len(faces)
    codes = getattr(col, "_codes3d", None)
    closed = np.full(n, bool(getattr(col, "_closed", True)))
    if codes is not None and len(codes) > 0:
        if len(codes) != n:
            return None
        for i, c in enumerate(codes):
            if c is None:
                continue
            c = np.asarray(c)
            if (c[1:] == Path.MOVETO).any():
                return None
            closed[i] = len(c) > 0 and c[-1] == Path.CLOSEPOLY
            if closed[i]:  # the closing vertex is not a point of the polygon
                padding[i, len(c) - 1] = True
    valid = ~padding
    bad = invalid(ax, faces[..., 0], faces[..., 1], faces[..., 2],
                  getattr(col, "_axlim_clip", False))
    keep = ~(bad & valid).any(axis=1) & (valid.sum(axis=1) >= 3)
    kept = np.flatnonzero(keep)
    fill = per_face(col._facecolor3d, n)[kept]
    edge = per_face(col._edgecolor3d, n)[kept]
    widths = cycled(np.asarray(col.get_linewidth(), dtype=float), n)
    widths = widths[kept] if len(widths) else np.zeros(len(kept))
    return Polygons(
        scaled(ax, faces[kept][valid[kept]]), valid[kept].sum(axis=1).astype(np.int64), kept,
        fill, edge, widths, ~closed[kept],
    )


def _faces(col) -> Tuple[np.ndarray, np.ndarray]:
    """A Poly3DCollection's faces (n, m, 3) and their padding (n, m)."""
    faces = getattr(col, "_faces", None)
    if faces is not None:
        faces = np.asarray(faces, dtype=float)
        n, m = faces.shape[:2]
        padding = np.broadcast_to(np.asarray(col._invalid_vertices, dtype=bool), (n, m)).copy()
        return faces, padding
    # matplotlib before 3.9: one array of points and slices.
    vec = np.asarray(col._vec)
    slices = col._segslices
    m = max((s.stop - s.start for s in slices), default=0)
    faces = np.zeros((len(slices), m, 3))
    padding = np.ones((len(slices), m), dtype=bool)
    for i, s in enumerate(slices):
        k = s.stop - s.start
        faces[i, :k] = vec[:3, s].T
        padding[i, :k] = False
    return faces, padding


def patch_polygon(ax, patch) -> Optional[Polygons]:
    """A Patch3D's outline as one polygon (curves of a PathPatch3D
    flattened); None when it has several subpaths."""
    pts = np.asarray(patch._segment3d, dtype=float).reshape(-1, 3)
    codes = getattr(patch, "_code3d", None)
    # matplotlib strokes a Patch3D's outline open (a polygon of a closed
    # patch repeats its first point), a PathPatch3D's as its codes say.
    closed = codes is not None and len(codes) > 0 and codes[-1] == Path.CLOSEPOLY
    if codes is not None:
        flat = flatten3d(pts, np.asarray(codes))
        if flat is None:
            return None
        pts = flat
    if len(pts) < 3 or invalid(ax, pts[:, 0], pts[:, 1], pts[:, 2],
                               getattr(patch, "_axlim_clip", False)).any():
        return Polygons(np.zeros((0, 3)), np.zeros(0, np.int64), np.zeros(0, np.int64),
                        np.zeros((0, 4)), np.zeros((0, 4)), np.zeros(0), np.zeros(0, bool))
    fill = np.asarray(patch.get_facecolor(), dtype=float).reshape(1, 4)
    if not patch.get_fill():
        fill = np.zeros((1, 4))
    edge = np.asarray(patch.get_edgecolor(), dtype=float).reshape(1, 4)
    width = 0.0 if patch.get_linestyle() in ("None", "none", "") else patch.get_linewidth()
    return Polygons(scaled(ax, pts), np.array([len(pts)], np.int64), np.array([0]), fill, edge,
                    np.array([float(width)]), np.array([not closed]))


def flatten3d(pts: np.ndarray, codes: np.ndarray, steps: int = 16) -> Optional[np.ndarray]:
    """A 3-D path of one subpath as a polyline: Bezier curves (CURVE3,
    CURVE4) evaluated at ``steps`` points; the CLOSEPOLY vertex dropped.
    None for several subpaths."""
    if len(codes) != len(pts) or (codes[1:] == Path.MOVETO).any():
        return None
    out = [pts[:1]]
    t = np.linspace(0, 1, steps + 1)[1:, None]
    k = 1
    while k < len(pts):
        c = codes[k]
        if c == Path.CURVE3 and k + 1 < len(pts):
            p0, p1, p2 = out[-1][-1], pts[k], pts[k + 1]
            out.append((1 - t) ** 2 * p0 + 2 * (1 - t) * t * p1 + t ** 2 * p2)
            k += 2
        elif c == Path.CURVE4 and k + 2 < len(pts):
            p0, p1, p2, p3 = out[-1][-1], pts[k], pts[k + 1], pts[k + 2]
            out.append((1 - t) ** 3 * p0 + 3 * (1 - t) ** 2 * t * p1
                       + 3 * (1 - t) * t ** 2 * p2 + t ** 3 * p3)
            k += 3
        elif c == Path.CLOSEPOLY:
            k += 1
        else:
            out.append(pts[k:k + 1])
            k += 1
    return np.concatenate(out)


@dataclass
class Polylines:
    """Polylines (scaled points, sizes) and, per polyline, its artist
    (index into the level's members) and its index within the artist."""

    pieces: List[np.ndarray] = field(default_factory=list)
    owner: List[int] = field(default_factory=list)
    index: List[int] = field(default_factory=list)

    def add(self, ax, member: int, index: int, pts, clip: bool) -> None:
        """Adds ``pts`` (k, 3), broken where a point is left out."""
        pts = np.asarray(np.ma.filled(np.ma.asarray(pts, dtype=float), np.nan))
        if pts.ndim != 2 or len(pts) < 2:
            return
        bad = invalid(ax, pts[:, 0], pts[:, 1], pts[:, 2], clip)
        if not bad.any():
            runs = [pts]
        else:
            cuts = np.flatnonzero(np.diff(bad.astype(np.int8))) + 1
            runs = [r for r, b in zip(np.split(pts, cuts), np.split(bad, cuts)) if not b[0]]
        for run in runs:
            if len(run) >= 2:
                self.pieces.append(scaled(ax, run))
                self.owner.append(member)
                self.index.append(index)


@dataclass
class Anchors:
    """Points (markers, labels) drawn whole: scaled points, and per point
    its artist (index into the level's members) and its index within the
    artist."""

    points: List[np.ndarray] = field(default_factory=list)
    owner: List[np.ndarray] = field(default_factory=list)
    index: List[np.ndarray] = field(default_factory=list)

    def add(self, ax, member: int, xs, ys, zs, clip: bool) -> None:
        xs, ys, zs = (np.asarray(np.ma.filled(np.ma.asarray(v, dtype=float), np.nan)).ravel()
                      for v in (xs, ys, zs))
        n = max(len(xs), len(ys), len(zs))
        xs, ys, zs = (np.broadcast_to(v, (n,)) for v in (xs, ys, zs))
        keep = np.flatnonzero(~invalid(ax, xs, ys, zs, clip))
        self.points.append(scaled(ax, np.column_stack([xs, ys, zs])[keep]))
        self.owner.append(np.full(len(keep), member))
        self.index.append(keep)

    def arrays(self) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
        if not self.points:
            return np.zeros((0, 3)), np.zeros(0, int), np.zeros(0, int)
        return (np.concatenate(self.points), np.concatenate(self.owner),
                np.concatenate(self.index))


def marked(line, n: int) -> np.ndarray:
    """The indices of a line's points that get a marker (``markevery``
    given as an int, a (start, step) pair, a slice, or a list or mask of
    points; a fraction of the length marks every point)."""
    every = line.get_markevery()
    idx = np.arange(n)
    if every is None:
        return idx
    if isinstance(every, (int, np.integer)) and not isinstance(every, bool):
        return idx[::max(int(every), 1)]
    if isinstance(every, tuple) and len(every) == 2 and all(
            isinstance(v, (int, np.integer)) for v in every):
        return idx[int(every[0])::max(int(every[1]), 1)]
    if isinstance(every, slice):
        return idx[every]
    a = np.asarray(every)
    if a.dtype == bool and len(a) == n:
        return idx[a]
    if a.dtype.kind in "iu":
        return a[(a >= 0) & (a < n)]
    return idx
