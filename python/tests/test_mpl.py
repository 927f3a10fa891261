"""plytrace.mpl against an independent oracle: figures saved as SVG, PDF
and PNG through the bridge are rasterized (librsvg, poppler, Agg) and
compared, pixel by pixel, with a numpy ray cast of the same triangles in
the same projection. Saved without the bridge, the same figures are
wrong, so the comparison can fail."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

import plytrace.mpl  # noqa: E402
import oracle  # noqa: E402
from oracle import PALETTE  # noqa: E402

#: Most wrong pixels allowed, percent of the interior pixels.
BOUND = 0.5

SIZE = (6.0, 5.0)


def _blocks(rows, cols, a, b, k=4):
    """Face colours in k x k blocks of palette colours a and b."""
    i, j = np.mgrid[0:rows, 0:cols]
    return np.where(((i // k + j // k) % 2)[..., None] == 0, PALETTE[a], PALETTE[b])


def _axes():
    fig = plt.figure(figsize=SIZE, dpi=oracle.DPI)
    ax = fig.add_subplot(projection="3d")
    return fig, ax


def two_surfaces():
    fig, ax = _axes()
    x = np.linspace(-2, 2, 25)
    X, Y = np.meshgrid(x, x)
    ax.plot_surface(X, Y, np.sin(1.5 * X) * np.cos(Y), facecolors=_blocks(25, 25, 0, 3),
                    shade=False, linewidth=0)
    ax.plot_surface(X, Y, 0.6 * X + 0.2 * Y, facecolors=_blocks(25, 25, 1, 5),
                    shade=False, linewidth=0)
    return fig, ax, None


def bar3d_city():
    fig, ax = _axes()
    rng = np.random.default_rng(7)
    x, y = np.meshgrid(np.arange(6), np.arange(6))
    x, y = x.ravel().astype(float), y.ravel().astype(float)
    heights = rng.uniform(0.5, 8, len(x))
    colors = PALETTE[(np.arange(len(x)) * 3) % len(PALETTE)]
    ax.bar3d(x, y, 0, 0.8, 0.8, heights, color=colors, shade=False)
    ax.view_init(elev=60, azim=-20)
    return fig, ax, None


def voxels():
    """A shell of voxels cut by a plane (matplotlib orders voxels alone
    well enough; it cannot order them with a surface through them)."""
    fig, ax = _axes()
    i, j, k = np.indices((6, 6, 6))
    filled = ((i - 2.5) ** 2 + (j - 2.5) ** 2 + (k - 2.5) ** 2 < 9) & ((i + j + k) % 3 != 0)
    colors = np.empty(filled.shape + (3,))
    colors[...] = PALETTE[((i + 2 * j + 3 * k) % 7)]
    ax.voxels(filled, facecolors=colors, shade=False)
    p = np.linspace(-0.5, 6.5, 8)
    PX, PY = np.meshgrid(p, p)
    ax.plot_surface(PX, PY, 3 + 0.3 * (PX - 3), color=PALETTE[7], shade=False, linewidth=0)
    return fig, ax, None


def torus_plane():
    fig, ax = _axes()
    u, v = np.meshgrid(np.linspace(0, 2 * np.pi, 41), np.linspace(0, 2 * np.pi, 21))
    R, r = 1.0, 0.4
    X = (R + r * np.cos(v)) * np.cos(u)
    Y = (R + r * np.cos(v)) * np.sin(u)
    Z = r * np.sin(v)
    ax.plot_surface(X, Y, Z, facecolors=_blocks(21, 41, 2, 4, k=3), shade=False, linewidth=0)
    p = np.linspace(-1.8, 1.8, 10)
    PX, PY = np.meshgrid(p, p)
    ax.plot_surface(PX, PY, 0.15 * PX, facecolors=_blocks(10, 10, 7, 6, k=20),
                    shade=False, linewidth=0)
    ax.set_zlim(-1.5, 1.5)
    return fig, ax, None


def surface_line():
    fig, ax = _axes()
    x = np.linspace(-2, 2, 25)
    X, Y = np.meshgrid(x, x)
    ax.plot_surface(X, Y, np.sin(X) * np.cos(Y), facecolors=_blocks(25, 25, 3, 5),
                    shade=False, linewidth=0)
    t = np.linspace(-1.8, 1.8, 60)
    line = np.column_stack([t, 0.6 * t, 0.9 * np.sin(2 * t)])
    ax.plot(line[:, 0], line[:, 1], line[:, 2], color="black", linewidth=3)
    return fig, ax, ([line], 3 * oracle.DPI / 72)


def wireframe_surface():
    """A wireframe crossing a surface (a Line3DCollection)."""
    fig, ax = _axes()
    x = np.linspace(-2, 2, 25)
    X, Y = np.meshgrid(x, x)
    ax.plot_surface(X, Y, 0.5 * np.sin(1.5 * X), facecolors=_blocks(25, 25, 1, 2),
                    shade=False, linewidth=0)
    Z2 = 0.6 * Y
    ax.plot_wireframe(X, Y, Z2, rstride=6, cstride=6, color="black", linewidth=2)
    wires = [np.column_stack([X[i], Y[i], Z2[i]]) for i in range(0, 25, 6)]
    wires += [np.column_stack([X[:, j], Y[:, j], Z2[:, j]]) for j in range(0, 25, 6)]
    return fig, ax, (wires, 2 * oracle.DPI / 72)


FIGURES = [two_surfaces, bar3d_city, voxels, torus_plane, surface_line, wireframe_surface]

needs_tools = pytest.mark.skipif(
    bool(oracle.tools_missing()),
    reason=f"missing rasterizers: {oracle.tools_missing()} (librsvg2-bin, poppler-utils)",
)


def score(make, fmt, bridge, tmp_path):
    fig, ax, line = make()
    path = tmp_path / f"{make.__name__}.{fmt}"
    if bridge:
        plytrace.mpl.savefig(fig, path, dpi=oracle.DPI)
    else:
        fig.savefig(path, dpi=oracle.DPI)
    size = tuple((fig.get_size_inches() * oracle.DPI).round().astype(int))
    img = oracle.rasterize(path, size)
    result = {}
    exclude = None
    if line is not None:
        polylines, width = line
        if isinstance(polylines, np.ndarray):
            polylines = [polylines]
        wrong = samples = 0
        exclude = np.zeros(img.shape[:2], dtype=bool)
        for points in polylines:
            score_, near, _ = oracle.line_score(fig, ax, img, points, width)
            wrong, samples = wrong + score_.wrong, samples + score_.pixels
            exclude |= near
        result["line"] = oracle.Score(wrong, samples)
    result["surface"] = oracle.surface_score(fig, ax, img, exclude)
    plt.close(fig)
    return result


@needs_tools
@pytest.mark.parametrize("fmt", ["svg", "pdf", "png"])
@pytest.mark.parametrize("make", FIGURES, ids=lambda f: f.__name__)
def test_the_bridge_draws_what_the_ray_cast_sees(make, fmt, tmp_path, results):
    s = score(make, fmt, True, tmp_path)
    results.append((make.__name__, fmt, "bridge", s))
    assert s["surface"].pixels > 5_000, s
    assert s["surface"].percent <= BOUND, s
    if "line" in s:
        assert s["line"].pixels > 1000, s
        assert s["line"].percent <= BOUND, s


@needs_tools
@pytest.mark.parametrize("fmt", ["svg", "pdf"])
@pytest.mark.parametrize("make", FIGURES, ids=lambda f: f.__name__)
def test_without_the_bridge_the_same_figures_are_wrong(make, fmt, tmp_path, results):
    s = score(make, fmt, False, tmp_path)
    results.append((make.__name__, fmt, "matplotlib", s))
    worst = max(v.percent for v in s.values())
    assert worst > BOUND, s


def test_fix_and_unfix_and_the_context():
    fig, ax, _ = two_surfaces()
    assert not plytrace.mpl.is_fixed(ax)
    plytrace.mpl.fix(ax)
    assert plytrace.mpl.is_fixed(ax)
    plytrace.mpl.unfix(fig)
    assert not plytrace.mpl.is_fixed(ax)
    with plytrace.mpl.fixed(fig):
        assert plytrace.mpl.is_fixed(ax)
    assert not plytrace.mpl.is_fixed(ax)
    with pytest.raises(TypeError, match="3-D Axes"):
        plytrace.mpl.fix(object())
    plt.close(fig)


def test_the_figure_is_unchanged_after_a_save(tmp_path):
    """The bridge changes nothing that stays: a plain save after it is the
    same as a plain save before it."""
    fig, ax, _ = surface_line()
    with matplotlib.rc_context({"svg.hashsalt": "plytrace"}):
        saves = []
        for k, how in enumerate([fig.savefig, lambda p, **kw: plytrace.mpl.savefig(fig, p, **kw),
                                 fig.savefig]):
            how(tmp_path / f"{k}.svg", metadata={"Date": None})
            saves.append((tmp_path / f"{k}.svg").read_bytes())
    assert saves[0] == saves[2]
    assert saves[0] != saves[1]
    plt.close(fig)


def test_edges_of_split_polygons_are_drawn_only_on_the_outline(tmp_path):
    """bar3d with black edges: a split face's pieces are filled without
    the cut lines, and its own edges stay."""
    fig, ax = _axes()
    ax.bar3d([0, 0.5], [0, 0.3], [0, 0.5], 1, 1, 1, color=["C0", "C1"], edgecolor="k",
             shade=False)
    plytrace.mpl.savefig(fig, tmp_path / "e.svg")
    plt.close(fig)
    assert (tmp_path / "e.svg").stat().st_size > 0


def test_markers_are_hidden_with_their_points(tmp_path):
    """A line's markers show at the points a surface does not hide."""
    fig, ax = _axes()
    x = np.linspace(-2, 2, 20)
    X, Y = np.meshgrid(x, x)
    ax.plot_surface(X, Y, 0 * X, color=PALETTE[1], shade=False, linewidth=0)
    t = np.linspace(-1.8, 1.8, 10)
    z = np.where(np.arange(10) % 2 == 0, 0.2, -0.2)  # above, below, above...
    ax.plot(t, 0 * t, z, linestyle="none", marker="o", markersize=8, color="black")
    ax.set_zlim(-2, 2)  # the points below stay inside the plane's picture
    path = tmp_path / "m.png"
    plytrace.mpl.savefig(fig, path, dpi=oracle.DPI)
    img = oracle.rasterize(path, tuple((fig.get_size_inches() * oracle.DPI).astype(int)))
    h = np.column_stack([t, 0 * t, z, np.ones(10)]) @ np.asarray(ax.M).T
    disp = ax.transData.transform(h[:, :2] / h[:, 3:])
    dark = [img[int(img.shape[0] - y), int(x)].max() < 0.25 for x, y in disp]
    assert dark == [k % 2 == 0 for k in range(10)], dark
    plt.close(fig)


def test_pgf_through_the_bridge(tmp_path):
    """The PGF backend draws the bridge's collection (no text, so no TeX
    is needed): fewer fills than matplotlib's own, one per run of a
    colour."""
    fig, ax, _ = two_surfaces()
    ax.set_axis_off()
    fig.savefig(tmp_path / "plain.pgf")
    plytrace.mpl.savefig(fig, tmp_path / "bridge.pgf")
    plain = (tmp_path / "plain.pgf").read_text().count("\\pgfusepath{fill}")
    bridge = (tmp_path / "bridge.pgf").read_text().count("\\pgfusepath{fill}")
    assert 0 < bridge < plain / 4, (bridge, plain)
    plt.close(fig)


@pytest.mark.parametrize("fmt", ["svg", "pdf", "png"])
def test_other_3d_artists_draw_through_the_bridge(fmt, tmp_path):
    """plot_trisurf, a translucent add_collection3d, contourf, quiver,
    scatter, text and a log axis: saved through the bridge without
    error, and translucent faces keep their alpha."""
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    fig = plt.figure(figsize=(8, 4))
    ax = fig.add_subplot(1, 2, 1, projection="3d")
    rng = np.random.default_rng(3)
    x, y = rng.uniform(-1, 1, (2, 60))
    ax.plot_trisurf(x, y, x * y, cmap="coolwarm")
    tri = Poly3DCollection([[(-1, -1, -0.5), (1, -1, 0.5), (0, 1, 0)]], alpha=0.5,
                           facecolor="tab:green", edgecolor="k")
    ax.add_collection3d(tri)
    ax.scatter(x, y, x * y, c="k", s=4)
    ax.quiver(0, 0, 0, 0.5, 0.5, 0.5)
    ax.text(0, 0, 1, "a label")
    bx = fig.add_subplot(1, 2, 2, projection="3d")
    X, Y = np.meshgrid(np.linspace(1, 10, 12), np.linspace(-1, 1, 12))
    bx.contourf(X, Y, np.sin(X) * Y, zdir="z", offset=-1)
    bx.plot_surface(X, Y, np.sin(X) * Y, alpha=0.7)
    try:
        bx.set_xscale("log")
    except Exception:  # matplotlib without 3-D log axes
        pass
    plytrace.mpl.savefig(fig, tmp_path / f"other.{fmt}")
    assert (tmp_path / f"other.{fmt}").stat().st_size > 1000
    if fmt == "svg":
        assert "fill-opacity: 0.5" in (tmp_path / "other.svg").read_text()
    plt.close(fig)
