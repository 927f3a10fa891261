"""An independent oracle for matplotlib 3-D figures: the triangles of the
axes' polygon collections, ray cast per pixel in the axes' projection
with numpy, and the comparison of a rasterized picture with it.

Each test figure paints its faces in colours of one palette (no shading),
so a pixel of the picture names the face colour seen there.
"""

from __future__ import annotations

import shutil
import subprocess
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from mpl_toolkits.mplot3d import art3d

#: Well separated colours for faces (RGB, 0 to 1); black is for lines.
PALETTE = np.array(
    [
        [0.90, 0.10, 0.10],
        [0.10, 0.35, 0.95],
        [0.10, 0.75, 0.20],
        [0.95, 0.80, 0.10],
        [0.60, 0.15, 0.75],
        [0.10, 0.80, 0.85],
        [0.95, 0.45, 0.75],
        [0.55, 0.35, 0.10],
    ]
)

DPI = 100


def triangles(ax):
    """The axes' polygons as triangles (fans from each polygon's first
    vertex, as plytrace cuts polygons that are not planar): their projected
    points (t, 3, 3) as (x, y, depth), and the palette index of each."""
    m = np.asarray(ax.M, dtype=float)
    tris, ids = [], []
    for col in ax.collections:
        if not isinstance(col, art3d.Poly3DCollection) or not col.get_visible():
            continue
        faces = np.asarray(col._faces, dtype=float)
        valid = ~np.broadcast_to(np.asarray(col._invalid_vertices, bool), faces.shape[:2])
        colors = np.asarray(col._facecolor3d)[:, :3]
        if len(colors) == 1:
            colors = np.repeat(colors, len(faces), axis=0)
        palette = np.argmin(((colors[:, None, :] - PALETTE[None]) ** 2).sum(-1), axis=1)
        for face, ok, pid in zip(faces, valid, palette):
            pts = face[ok]
            for k in range(1, len(pts) - 1):
                tris.append([pts[0], pts[k], pts[k + 1]])
                ids.append(pid)
    tris = np.asarray(tris, dtype=float).reshape(-1, 3, 3)
    h = np.concatenate([tris, np.ones(tris.shape[:2] + (1,))], axis=2) @ m.T
    return h[..., :3] / h[..., 3:], np.asarray(ids)


def pixel_grid(fig, ax):
    """The projected 2-D coordinates of every pixel centre of the picture
    at DPI, and the pixels of the axes' area."""
    w, h = (fig.get_size_inches() * DPI).round().astype(int)
    scale = DPI / fig.dpi
    jj, ii = np.mgrid[0:h, 0:w]
    display = np.column_stack([(ii.ravel() + 0.5) / scale, (h - jj.ravel() - 0.5) / scale])
    xy = ax.transData.inverted().transform(display).reshape(h, w, 2)
    bbox = ax.bbox
    inside = (
        (display[:, 0] >= bbox.x0)
        & (display[:, 0] <= bbox.x1)
        & (display[:, 1] >= bbox.y0)
        & (display[:, 1] <= bbox.y1)
    ).reshape(h, w)
    return xy, inside


def ray_cast(xy, tris, ids):
    """For each pixel, the palette index of the nearest triangle its ray
    meets (-1: none) and that triangle's depth; per triangle the depth
    along the ray through the pixel centre, nearest kept."""
    h, w = xy.shape[:2]
    depth = np.full((h, w), np.inf)
    seen = np.full((h, w), -1)
    x0, y0 = xy[0, 0]
    dx = xy[0, 1, 0] - x0
    dy = xy[1, 0, 1] - y0
    for t, pid in zip(tris, ids):
        (ax_, ay, az), (bx, by, bz), (cx, cy, cz) = t
        det = (bx - ax_) * (cy - ay) - (cx - ax_) * (by - ay)
        if det == 0:
            continue
        cols = sorted(((min(ax_, bx, cx) - x0) / dx, (max(ax_, bx, cx) - x0) / dx))
        rows = sorted(((min(ay, by, cy) - y0) / dy, (max(ay, by, cy) - y0) / dy))
        i0, i1 = max(int(np.floor(cols[0])), 0), min(int(np.ceil(cols[1])) + 1, w)
        j0, j1 = max(int(np.floor(rows[0])), 0), min(int(np.ceil(rows[1])) + 1, h)
        if i0 >= i1 or j0 >= j1:
            continue
        px = xy[j0:j1, i0:i1, 0]
        py = xy[j0:j1, i0:i1, 1]
        u = ((px - ax_) * (cy - ay) - (cx - ax_) * (py - ay)) / det
        v = ((bx - ax_) * (py - ay) - (px - ax_) * (by - ay)) / det
        hit = (u >= 0) & (v >= 0) & (u + v <= 1)
        z = az + u * (bz - az) + v * (cz - az)
        nearer = hit & (z < depth[j0:j1, i0:i1])
        depth[j0:j1, i0:i1][nearer] = z[nearer]
        seen[j0:j1, i0:i1][nearer] = pid
    return seen, depth


def interior(seen, inside, margin=2):
    """Pixels whose whole (2 margin + 1)-square sees one face colour, in
    the axes' area."""
    ok = inside & (seen >= 0)
    h, w = seen.shape
    pad = np.pad(seen, margin, constant_values=-2)
    for dj in range(-margin, margin + 1):
        for di in range(-margin, margin + 1):
            ok &= pad[margin + dj : margin + dj + h, margin + di : margin + di + w] == seen
    return ok


def classify(rgb):
    """The palette index nearest each pixel's colour."""
    d = ((rgb[..., None, :] - PALETTE[None, None]) ** 2).sum(-1)
    return np.argmin(d, axis=-1)


def rasterize(path: Path, size) -> np.ndarray:
    """A saved figure as an (h, w, 3) float array at DPI, by an independent
    rasterizer: librsvg for SVG, poppler for PDF, matplotlib's image
    reader for PNG."""
    w, h = size
    if path.suffix == ".svg":
        out = path.with_suffix(".svg.png")
        subprocess.run(
            ["rsvg-convert", "-w", str(w), "-h", str(h), "-b", "white", "-o", str(out), str(path)],
            check=True,
        )
        path = out
    elif path.suffix == ".pdf":
        stem = path.with_suffix("")
        subprocess.run(
            ["pdftoppm", "-r", str(DPI), "-png", "-singlefile", str(path), str(stem)],
            check=True,
        )
        path = stem.with_suffix(".png")
    import matplotlib.image

    img = matplotlib.image.imread(str(path))
    if img.dtype == np.uint8:
        img = img / 255.0
    img = img[..., :3]
    assert img.shape[:2] == (h, w), (img.shape, (h, w))
    return img


def tools_missing():
    return [t for t in ("rsvg-convert", "pdftoppm") if shutil.which(t) is None]


@dataclass
class Score:
    wrong: int
    pixels: int

    @property
    def percent(self) -> float:
        return 100.0 * self.wrong / max(self.pixels, 1)


def surface_score(fig, ax, img, exclude=None) -> Score:
    """Wrong face colour among the interior pixels of the plot area."""
    xy, inside = pixel_grid(fig, ax)
    tris, ids = triangles(ax)
    seen, _ = ray_cast(xy, tris, ids)
    ok = interior(seen, inside)
    if exclude is not None:
        ok &= ~exclude
    wrong = (classify(img) != seen) & ok
    return Score(int(wrong.sum()), int(ok.sum()))


def line_score(fig, ax, img, line3d: np.ndarray, width_px: float):
    """The line's samples seen (or hidden) where the picture does not show
    it (or shows it): samples along the line, each visible when no
    triangle is nearer along its ray, away from the ends of visible runs.
    Also the pixels near the line (to leave out of the surface score)."""
    m = np.asarray(ax.M, dtype=float)
    n = max(40_000 // (len(line3d) - 1), 20)  # samples per segment
    t = np.linspace(0, 1, n)[:, None]
    pts = np.concatenate([line3d[i] + t * (line3d[i + 1] - line3d[i]) for i in range(len(line3d) - 1)])
    h4 = np.column_stack([pts, np.ones(len(pts))]) @ m.T
    p = h4[:, :3] / h4[:, 3:]
    tris, _ = triangles(ax)
    visible = np.ones(len(p), dtype=bool)
    ta, tb, tc = tris[:, 0], tris[:, 1], tris[:, 2]
    det = (tb[:, 0] - ta[:, 0]) * (tc[:, 1] - ta[:, 1]) - (tc[:, 0] - ta[:, 0]) * (tb[:, 1] - ta[:, 1])
    ok = det != 0
    ta, tb, tc, det = ta[ok], tb[:, :][ok], tc[ok], det[ok]
    for k in range(0, len(p), 256):
        q = p[k : k + 256]
        px, py = q[:, 0:1], q[:, 1:2]
        u = ((px - ta[:, 0]) * (tc[:, 1] - ta[:, 1]) - (tc[:, 0] - ta[:, 0]) * (py - ta[:, 1])) / det
        v = ((tb[:, 0] - ta[:, 0]) * (py - ta[:, 1]) - (px - ta[:, 0]) * (tb[:, 1] - ta[:, 1])) / det
        hit = (u >= 0) & (v >= 0) & (u + v <= 1)
        z = ta[:, 2] + u * (tb[:, 2] - ta[:, 2]) + v * (tc[:, 2] - ta[:, 2])
        z = np.where(hit, z, np.inf).min(axis=1)
        visible[k : k + 256] = q[:, 2] <= z
    # Pixel positions of the samples.
    scale = DPI / fig.dpi
    disp = ax.transData.transform(p[:, :2]) * scale
    hpx = img.shape[0]
    col = np.floor(disp[:, 0]).astype(int)
    row = np.floor(hpx - disp[:, 1]).astype(int)
    inb = (col >= 0) & (col < img.shape[1]) & (row >= 0) & (row < hpx)
    # Away from changes of visibility (3 pixels along the line).
    steps = np.hypot(np.diff(disp[:, 0]), np.diff(disp[:, 1]))
    arc = np.concatenate([[0], np.cumsum(steps)])
    change = arc[np.flatnonzero(np.diff(visible.astype(int))) + 1]
    far = np.ones(len(p), dtype=bool)
    for c in change:
        far &= np.abs(arc - c) > 3 + width_px
    use = inb & far
    dark = img[row[use], col[use]].max(axis=-1) < 0.25
    wrong = (dark != visible[use]).sum()
    # Pixels near the line.
    near = np.zeros(img.shape[:2], dtype=bool)
    r = int(np.ceil(width_px / 2 + 2))
    for dj in range(-r, r + 1):
        for di in range(-r, r + 1):
            rr, cc = row[inb] + dj, col[inb] + di
            good = (rr >= 0) & (rr < hpx) & (cc >= 0) & (cc < img.shape[1])
            near[rr[good], cc[good]] = True
    return Score(int(wrong), int(use.sum())), near, visible
