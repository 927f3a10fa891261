"""One draw of a set of 3-D artists painted in one order (a *level*: all
of an axes' 3-D artists, or those of one zorder when the axes'
``computed_zorder`` is off): plytrace's NNS paint order of their
polygons' pieces, with the lines' visible parts and the markers and
labels placed in it (``Projection.layered``), drawn as runs.

Each run is drawn by its own artist, with its state swapped for the time
of the call (the paths, colours and widths of the run): so the artist's
gid, url, clip path, hatch, rasterization, sketch and path effects are
its own. Between draws every artist holds what matplotlib's own
projection put there (the 2-D paths of ``get_paths``, ``contains`` and
picking)."""

from __future__ import annotations

import contextlib
import threading
import warnings
from typing import Dict, Iterator, List, Optional, Tuple

import numpy as np
from matplotlib import collections as mcoll
from matplotlib import lines as mlines
from matplotlib import patches as mpatches
from matplotlib.path import Path
from mpl_toolkits.mplot3d import art3d

from . import _mpl_gather as gather
from ._native import Projection

_MISSING = object()
_TRANSPARENT = np.zeros(4)
_NOTHING = (np.zeros((0, 2)), np.zeros(0, np.uint8), np.zeros(1, np.int64))

#: The 3-D artists a level orders.
POLYGONS = (art3d.Poly3DCollection, art3d.Patch3D)
LINES = (art3d.Line3D, art3d.Line3DCollection)
POINTS = (art3d.Path3DCollection, art3d.Text3D)


def member(artist) -> bool:
    """Whether a level takes ``artist`` (a scatter only where this
    matplotlib keeps what the bridge needs to draw a part of it)."""
    if isinstance(artist, art3d.Path3DCollection):
        return hasattr(artist, "_offset_zordered") and hasattr(artist, "_z_markers_idx")
    if isinstance(artist, art3d.Patch3D):
        return hasattr(artist, "_segment3d")
    return isinstance(artist, POLYGONS + LINES + POINTS)


@contextlib.contextmanager
def swapped(artist, **attrs) -> Iterator[None]:
    """``artist``'s attributes set for the time of the block (in its
    ``__dict__``, so nothing goes stale), then put back."""
    old = {k: artist.__dict__.get(k, _MISSING) for k in attrs}
    artist.__dict__.update(attrs)
    try:
        yield
    finally:
        for k, v in old.items():
            if v is _MISSING:
                artist.__dict__.pop(k, None)
            else:
                artist.__dict__[k] = v


def _paths(verts, codes, starts) -> List[Path]:
    make = getattr(Path, "_fast_from_codes_and_verts", None)
    if make is None:
        return [Path(verts[a:b], codes[a:b]) for a, b in zip(starts[:-1], starts[1:])]
    return [make(verts[a:b], codes[a:b]) for a, b in zip(starts[:-1], starts[1:])]


class Level:
    """The artists of one level and their one draw."""

    def __init__(self, ax, members: list, renderer):
        self.ax = ax
        self.members = members
        self.renderer = renderer
        self.drawn = False
        # The members the axes projects before drawing anything: once all
        # are, the order is computed in a thread while the axes draws its
        # panes, grid and ticks.
        self.unprojected = {id(m) for m in members
                            if isinstance(m, (mcoll.Collection, mpatches.Patch))}
        self.job: Optional[_Draw] = None

    def projected(self, artist) -> None:
        """After matplotlib's own projection of a member."""
        self.unprojected.discard(id(artist))
        if not self.unprojected and self.job is None and not self.drawn:
            self.job = _Draw(self)
            self.job.start()

    def draw_member(self, artist, renderer) -> None:
        """Any member's draw: the first draws the whole level."""
        if self.drawn:
            return
        self.drawn = True
        job = self.job or _Draw(self)
        if self.job is None:
            job.start()
        job.finish(renderer)


class _Draw:
    """What one draw of a level computes, and the draw."""

    def __init__(self, level: Level):
        self.ax = level.ax
        self.members = level.members
        self.renderer = level.renderer
        self.gids: Dict[int, int] = {}
        self.scatter_colors: Dict[int, Optional[tuple]] = {}
        self.thread: Optional[threading.Thread] = None
        self.result: Optional[tuple] = None
        self.error: Optional[BaseException] = None

    # Gathering

    def _polygons(self):
        """Per member its polygons (or None)."""
        per = []
        for m in self.members:
            if isinstance(m, art3d.Poly3DCollection):
                per.append(gather.collection_polygons(self.ax, m))
            elif isinstance(m, art3d.Patch3D):
                per.append(gather.patch_polygon(self.ax, m))
            else:
                per.append(None)
        return per

    def start(self) -> None:
        """Reads the members, and starts the order's computation."""
        per = self.polys = self._polygons()
        taken = [p for p in per if p is not None]
        if not taken:  # nothing can hide anything: matplotlib's own draws
            return
        self.owner = np.concatenate(
            [np.full(len(p.sizes), k) for k, p in enumerate(per) if p is not None])
        cat = lambda name: np.concatenate([getattr(p, name) for p in taken])  # noqa: E731
        self.fill, self.edge, self.widths = cat("fill"), cat("edge"), cat("widths")
        self.first_of = {}
        at = 0
        for k, p in enumerate(per):
            if p is not None:
                self.first_of[k] = at
                at += len(p.sizes)
        self.lines, anchors = self._lines_and_anchors()
        self.anchors = anchors.arrays()
        keys, grown, grow = self._keys_and_growth()
        lines = self.lines
        args = (
            (np.ascontiguousarray(cat("points"), dtype=float),
             np.ascontiguousarray(cat("sizes"), dtype=np.int64),
             np.ascontiguousarray(self.ax.M, dtype=float),
             np.ascontiguousarray(cat("open"), dtype=bool)),
            (grow, np.ascontiguousarray(grown), np.ascontiguousarray(keys),
             np.ascontiguousarray(self.fill[:, 3] >= 1.0),
             np.ascontiguousarray(
                 np.concatenate(lines.pieces) if lines.pieces else np.zeros((0, 3)), dtype=float),
             np.array([len(p) for p in lines.pieces], dtype=np.int64),
             np.ascontiguousarray(self.anchors[0], dtype=float)),
        )
        self.thread = threading.Thread(target=self._compute, args=args, daemon=True)
        self.thread.start()

    def _compute(self, new_args, layered_args) -> None:
        """In the thread: plytrace's part (the GIL released)."""
        try:
            self.result = Projection(*new_args).layered(*layered_args)
        except BaseException as e:  # raised again in the drawing thread
            self.error = e

    def finish(self, renderer) -> None:
        """Waits for the order and draws it."""
        self.renderer = renderer
        if self.thread is not None:
            self.thread.join()
            if self.error is not None:
                raise self.error
            self._paint()
        self._fallback(self.polys)

    def _fallback(self, per) -> None:
        """Members the bridge could not take, drawn by matplotlib (after
        the level); and the lines' 2-D data as matplotlib's own draw
        leaves it (for picking)."""
        for k, m in enumerate(self.members):
            if isinstance(m, POLYGONS) and per[k] is None:
                type(m).draw(m, self.renderer)
            elif isinstance(m, art3d.Line3D):
                xy = self._project(np.column_stack([np.ravel(v) for v in _data3d(m)]), m)
                mlines.Line2D.set_data(m, xy[:, 0], xy[:, 1])
            elif not any(p is not None for p in per):
                type(m).draw(m, self.renderer)

    def _lines_and_anchors(self):
        lines, anchors = gather.Polylines(), gather.Anchors()
        for k, m in enumerate(self.members):
            clip = getattr(m, "_axlim_clip", False)
            if isinstance(m, art3d.Line3D):
                pts = np.column_stack([np.ravel(v) for v in _data3d(m)])
                if m.get_linestyle() not in ("None", "none", "", " "):
                    lines.add(self.ax, k, 0, pts, clip)
                if _has_markers(m):
                    idx = gather.marked(m, len(pts))
                    anchors.add(self.ax, k, *pts[idx].T, clip)
                    anchors.index[-1] = idx[anchors.index[-1]]
            elif isinstance(m, art3d.Line3DCollection):
                for i, seg in enumerate(m._segments3d):
                    lines.add(self.ax, k, i, seg, clip)
            elif isinstance(m, art3d.Path3DCollection):
                anchors.add(self.ax, k, *m._offsets3d, clip)
            elif isinstance(m, art3d.Text3D):
                anchors.add(self.ax, k, m._x, m._y, m._z, clip)
        return lines, anchors

    def _project(self, xyz: np.ndarray, artist) -> np.ndarray:
        """Points through the axes' scales and projection (NaN where
        matplotlib leaves them out)."""
        bad = gather.invalid(self.ax, xyz[:, 0], xyz[:, 1], xyz[:, 2],
                             getattr(artist, "_axlim_clip", False))
        xyz = gather.scaled(self.ax, np.where(bad[:, None], np.nan, xyz))
        h = np.column_stack([xyz, np.ones(len(xyz))]) @ np.asarray(self.ax.M, dtype=float).T
        with np.errstate(all="ignore"):
            return h[:, :2] / h[:, 3:]

    # The paint order

    def _keys_and_growth(self):
        """Opaque faces without edges of one colour in one artist are
        filled together where the order allows; they are also grown by
        half the seam width (see ``plytrace.mpl.fix``)."""
        fill, edge, widths = self.fill, self.edge, self.widths
        stroked = (edge[:, 3] > 0) & (widths > 0)
        grown = ~stroked & (fill[:, 3] >= 1.0)
        # One number per colour (16 bits a channel) and artist.
        q = np.round(np.clip(fill, 0, 1) * 65535).astype(np.uint64)
        packed = (q[:, 0] << 48) | (q[:, 1] << 32) | (q[:, 2] << 16) | q[:, 3]
        _, same = np.unique(packed, return_inverse=True)
        _, same = np.unique(same.reshape(-1) * len(self.members) + self.owner,
                            return_inverse=True)
        same = same.reshape(-1)
        keys = np.where(grown, same, same.max(initial=0) + 1 + np.arange(len(fill)))
        grow = None
        seam = getattr(self.ax, "_plytrace_seam_width", 0.3)
        if seam > 0 and grown.any():
            half = seam / 2 * self.renderer.points_to_pixels(1.0)
            m = self.ax.transData.get_affine().get_matrix()
            sx, sy = np.hypot(m[0, 0], m[1, 0]), np.hypot(m[0, 1], m[1, 1])
            if sx > 0 and sy > 0:
                grow = (half / sx, half / sy)
        return keys.astype(np.uint32), grown, grow

    def _paint(self) -> None:
        assert self.result is not None
        paint, runs, slots = self.result
        sources, whole, fills, edges, _splits, warning = paint
        if warning:
            warnings.warn(f"plytrace.mpl: {warning}", RuntimeWarning, stacklevel=2)
        self.patches = _Patches(self, np.asarray(sources), np.asarray(whole), fills, edges)
        apoints, aowner, aindex = self.anchors
        self.anchor_index = aindex
        depth = self._depth(apoints)
        items = _items(self.lines, runs, slots, aowner, aindex, depth, len(sources))
        self._draw_in_order(items, runs, apoints)

    def _depth(self, points: np.ndarray) -> np.ndarray:
        h = np.column_stack([points, np.ones(len(points))]) @ np.asarray(self.ax.M, float).T
        with np.errstate(all="ignore"):
            return h[:, 2] / h[:, 3]

    # Drawing

    def _draw_in_order(self, items, runs, apoints) -> None:
        """The patches in runs of one artist, with the items of each slot
        drawn before the patch of that slot."""
        n = len(self.patches.sources)
        bounds = sorted({s for s, *_ in items} | {n})
        at = 0
        by_slot: Dict[int, list] = {}
        for item in items:
            by_slot.setdefault(item[0], []).append(item)
        for s in bounds:
            self.patches.draw_range(at, min(s, n))
            at = min(s, n)
            for group in _groups(by_slot.get(s, [])):
                self._draw_items(group, runs, apoints)

    def _draw_items(self, group, runs, apoints) -> None:
        k = group[0][2]
        artist = self.members[k]
        gid = self.gid(artist)
        if group[0][1] == 0:  # line runs
            xy_all, _, _, starts = runs
            parts = [xy_all[starts[r]:starts[r + 1]] for _, _, _, r, _ in group]
            index = [i for *_, i in group]
            if isinstance(artist, art3d.Line3D):
                _draw_line(artist, parts, self.renderer, gid)
            else:
                _draw_line_collection(artist, parts, index, self.renderer, gid)
            return
        order = sorted(group, key=lambda g: -g[4])
        which = np.array([g[3] for g in order])
        if isinstance(artist, art3d.Line3D):
            _draw_markers(artist, self._project_points(apoints, which), self.renderer, gid)
        elif isinstance(artist, art3d.Path3DCollection):
            colors = self.scatter_colors.get(id(artist))
            if colors is None:
                colors = self.scatter_colors[id(artist)] = _scatter_colors(artist)
            _draw_scatter(artist, np.asarray(self.anchor_index)[which], self.renderer, gid,
                          colors)
        else:
            with swapped(artist, _gid=gid):
                type(artist).draw(artist, self.renderer)

    def _project_points(self, apoints, which) -> np.ndarray:
        pts = apoints[which]
        h = np.column_stack([pts, np.ones(len(pts))]) @ np.asarray(self.ax.M, float).T
        return h[:, :2] / h[:, 3:]

    def gid(self, artist):
        """The artist's gid for its next run: its own for the first, then
        numbered (ids are unique in an SVG)."""
        gid = artist.get_gid()
        k = self.gids.get(id(artist), 0)
        self.gids[id(artist)] = k + 1
        return gid if gid is None or k == 0 else f"{gid}-{k + 1}"


def _data3d(line) -> List[np.ndarray]:
    """A Line3D's points as three arrays of one length (NaN where masked)."""
    data: List[np.ndarray] = [np.ravel(np.ma.filled(np.ma.asarray(v, dtype=float), np.nan))
            for v in line.get_data_3d()]
    n = max(len(v) for v in data)
    return [np.broadcast_to(v, (n,)) for v in data]


def _has_markers(line) -> bool:
    return line.get_marker() not in (None, "None", "none", "", " ") and line.get_markersize() > 0


def _items(lines, runs, slots, aowner, aindex, depth, n):
    """What is drawn among the patches: (slot, kind, member, which,
    depth) for each line run (kind 0, which: the run) and each anchor
    (kind 1, which: the anchor)."""
    _, run_line, run_slot, _ = runs
    items = []
    for r, (line, slot) in enumerate(zip(run_line, run_slot)):
        items.append((int(slot), 0, lines.owner[line], r, lines.index[line]))
    for a, slot in enumerate(slots):
        if slot >= 0:
            items.append((int(slot), 1, int(aowner[a]), a, float(depth[a])))
    return items


def _groups(items: list) -> list:
    """The items of one slot in groups of one member and kind: lines
    first, then markers and labels, farthest group first."""
    groups: Dict[Tuple[int, int], list] = {}
    for item in items:
        groups.setdefault((item[1], item[2]), []).append(item)

    def key(k):
        kind, _ = k
        far = -max(g[4] for g in groups[k]) if kind == 1 else 0.0
        return (kind, far, k[1])
    return [groups[k] for k in sorted(groups, key=key)]


class _Patches:
    """The patches of a paint order as paths, drawn in runs of one
    artist."""

    def __init__(self, draw: _Draw, sources, whole, fills, edges):
        self.draw = draw
        self.sources = sources
        d = draw
        self.artist = d.owner[sources] if len(sources) else np.zeros(0, int)
        stroked = (d.edge[:, 3] > 0) & (d.widths > 0)
        self.whole = whole.astype(bool)
        self.split = stroked[sources] & ~self.whole
        self.fill_paths = _paths(*fills)
        ev, ecodes, estarts = edges
        self.edge_paths = {int(p): Path(ev[estarts[p]:estarts[p + 1]],
                                        ecodes[estarts[p]:estarts[p + 1]])
                           for p in np.flatnonzero(self.split) if estarts[p + 1] > estarts[p]}

    def draw_range(self, a: int, b: int) -> None:
        """Patches a to b (exclusive), in runs of one artist."""
        if b <= a:
            return
        cuts = np.flatnonzero(np.diff(self.artist[a:b])) + 1 + a
        for lo, hi in zip(np.concatenate([[a], cuts]), np.concatenate([cuts, [b]])):
            k = int(self.artist[lo])
            m = self.draw.members[k]
            if isinstance(m, art3d.Patch3D):
                self._draw_patch(m, k, int(lo), int(hi))
            else:
                self._draw_collection(m, k, int(lo), int(hi))

    def _draw_collection(self, col, k: int, a: int, b: int) -> None:
        d = self.draw
        patches = np.arange(a, b)
        paths = self.fill_paths[a:b]
        src = self.sources[a:b]
        face = d.fill[src]
        edge = np.where(self.split[a:b, None], _TRANSPARENT, d.edge[src])
        extra = [int(p) for p in patches if int(p) in self.edge_paths]
        if extra:
            # Each edge path right after its patch.
            keys = np.concatenate([patches * 2.0, np.array(extra) * 2.0 + 1])
            order = np.argsort(keys, kind="stable")
            paths = [(paths + [self.edge_paths[p] for p in extra])[i] for i in order]
            face = np.concatenate([face, np.zeros((len(extra), 4))])[order]
            edge = np.concatenate([edge, d.edge[self.sources[extra]]])[order]
            src = np.concatenate([src, self.sources[extra]])[order]
        faces = d.polys[k].kept[src - d.first_of[k]]
        style = _face_styles(col, faces)
        if len(paths) == 1 and not (self.whole[a] and _rings(paths[0]) == 1):
            # Two rows keep a single path of pieces from being drawn as a
            # marker, which Agg snaps to whole pixels (opening the seams
            # between pieces); one whole polygon is drawn as matplotlib
            # draws it.
            face = np.repeat(face, 2, axis=0)
        with swapped(col, _paths=paths, _facecolors2d=face, _edgecolors2d=_one(edge),
                     _gid=d.gid(col), **style):
            mcoll.PolyCollection.draw(col, d.renderer)

    def _draw_patch(self, patch, k: int, a: int, b: int) -> None:
        d = self.draw
        gid = d.gid(patch)
        paths = self.fill_paths[a:b]
        if b - a == 1 and self.whole[a]:  # whole: as matplotlib draws it
            with swapped(patch, _gid=gid):
                mpatches.Patch.draw(patch, d.renderer)
            return
        if not self.split[a:b].any():  # no edges cut: its pieces as one path
            with swapped(patch, _path2d=Path.make_compound_path(*paths), _gid=gid):
                mpatches.Patch.draw(patch, d.renderer)
            return
        with swapped(patch, _path2d=Path.make_compound_path(*paths), _edgecolor=_TRANSPARENT,
                     _gid=gid):
            mpatches.Patch.draw(patch, d.renderer)
        edges = [self.edge_paths[p] for p in range(a, b) if p in self.edge_paths]
        if edges:
            with swapped(patch, _path2d=Path.make_compound_path(*edges), _facecolor=_TRANSPARENT,
                         _hatch=None, _gid=None):
                mpatches.Patch.draw(patch, d.renderer)


def _rings(path: Path) -> int:
    return 1 if path.codes is None else int(np.count_nonzero(path.codes == Path.MOVETO))


def _one(values: np.ndarray) -> np.ndarray:
    """Per-path colours as one row when all rows agree (the backends then
    set it once), or none when all are transparent (nothing stroked)."""
    if len(values) and (values[:, 3] == 0).all():
        return values[:0]
    if len(values) > 1 and (values == values[0]).all():
        return values[:1]
    return values


def _face_styles(col, faces: np.ndarray) -> dict:
    """A collection's per-face line widths, styles, anti-aliasing and urls
    for the paths of ``faces``."""
    out = {}
    for name in ("_linewidths", "_linestyles", "_antialiaseds", "_urls"):
        values = getattr(col, name, None)
        if values is None:
            continue
        if len(values) <= 1:
            out[name] = values
            continue
        picked = [values[i % len(values)] for i in faces]
        out[name] = np.asarray(picked) if name in ("_linewidths", "_antialiaseds") else picked
    return out


def _draw_line(line, parts, renderer, gid) -> None:
    """Parts of a Line3D (2-D, NaN between pieces), without markers."""
    xy = np.concatenate([np.concatenate([p, np.full((1, 2), np.nan)]) for p in parts])[:-1]
    with swapped(line, _markersize=0, _gid=gid):
        mlines.Line2D.set_data(line, xy[:, 0], xy[:, 1])
        mlines.Line2D.draw(line, renderer)


def _draw_markers(line, xy, renderer, gid) -> None:
    """Markers of a Line3D at the 2-D points ``xy``."""
    with swapped(line, _linestyle="None", _markevery=None, _gid=gid):
        mlines.Line2D.set_data(line, xy[:, 0], xy[:, 1])
        mlines.Line2D.draw(line, renderer)


def _draw_line_collection(col, parts, index, renderer, gid) -> None:
    """Parts of a Line3DCollection's lines (``index``: each part's line)."""
    index = np.asarray(index)
    paths = [Path(p) for p in parts]
    style = {}
    for name in ("_edgecolors", "_linewidths", "_linestyles", "_antialiaseds"):
        values = getattr(col, name, None)
        if values is None or len(values) <= 1 or isinstance(values, str):
            continue
        picked = [values[i % len(values)] for i in index]
        style[name] = picked if name == "_linestyles" else np.asarray(picked)
    with swapped(col, _paths=paths, _gid=gid, _A=None, **style):
        mcoll.LineCollection.draw(col, renderer)


def _scatter_colors(col) -> Optional[tuple]:
    """A scatter's face and edge colours of all its points in their own
    order, depth-shaded as matplotlib shades them, computed once for all
    the scatter's runs (matplotlib shades all points at each call of
    ``get_facecolor``: once per run, it would cost the whole scatter per
    marker drawn among the polygons). None where a run's colours are not
    these rows picked by the run's points (an array of alphas with a
    single colour: matplotlib then leaves them in the points' order)."""
    if np.ndim(col._alpha) > 0 or col._vzs is None:
        return None
    with swapped(col, _z_markers_idx=np.arange(len(col._vzs))):
        return col.get_facecolor(), col.get_edgecolor()


def _draw_scatter(col, index: np.ndarray, renderer, gid, colors=None) -> None:
    """The markers ``index`` (in painting order) of a scatter (``colors``:
    its ``_scatter_colors``)."""
    xy = np.ma.getdata(col._offsets)[index] if len(col._offsets) > 1 else col._offsets
    style = {"_offset_zordered": np.asarray(xy), "_z_markers_idx": index, "_gid": gid}
    if colors is not None:
        face, edge = (c[index] if len(c) > 1 else c for c in colors)
        style.update(get_facecolor=lambda: face, get_edgecolor=lambda: edge)
    for name, three in (("_sizes", "_sizes3d"), ("_linewidths", "_linewidths3d")):
        values = getattr(col, three, None)
        if values is not None and len(values) > 1:
            style[name] = np.asarray(values)[index]
    with swapped(col, **style):
        art3d.Path3DCollection.draw(col, renderer)
