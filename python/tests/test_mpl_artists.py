"""plytrace.mpl with what mplot3d users do beyond opaque surfaces:
translucent and unfilled polygons, axlim_clip, open polygons, picking,
per-collection attributes, computed_zorder, pickling, markers, text,
patches, hatching and subfigures. Each test compares with a numpy oracle
(the projected points of the figure) or with matplotlib's own picture
where matplotlib draws it right."""

from __future__ import annotations

import copy
import io
import pickle
import re

import matplotlib

matplotlib.use("Agg")

import matplotlib.image as mimage  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.backend_bases import MouseEvent  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # noqa: E402

import plytrace.mpl  # noqa: E402

DPI = 100
RED = np.array([1.0, 0.0, 0.0])
BLUE = np.array([0.0, 0.0, 1.0])


def _png(fig, bridge: bool) -> np.ndarray:
    buf = io.BytesIO()
    if bridge:
        plytrace.mpl.savefig(fig, buf, format="png", dpi=DPI)
    else:
        fig.savefig(buf, format="png", dpi=DPI)
    buf.seek(0)
    return mimage.imread(buf)[..., :3]


def _pixel(fig, ax, xyz):
    """Row and column of the pixel showing the 3-D point(s) ``xyz``."""
    xyz = np.atleast_2d(np.asarray(xyz, dtype=float))
    h = np.column_stack([xyz, np.ones(len(xyz))]) @ np.asarray(ax.get_proj()).T
    disp = ax.transData.transform(h[:, :2] / h[:, 3:]) * DPI / fig.dpi
    height = int(round(fig.get_size_inches()[1] * DPI))
    return (height - disp[:, 1]).astype(int), disp[:, 0].astype(int)


def _near(img, color, tol=0.12):
    return (np.abs(img - color) < tol).all(axis=-1)


def _plane(ax, z=0.0, n=6, **kw):
    x = np.linspace(-1, 1, n)
    X, Y = np.meshgrid(x, x)
    return ax.plot_surface(X, Y, z + 0 * X, **kw)


def _figure():
    fig = plt.figure(figsize=(4, 4), dpi=DPI)
    ax = fig.add_subplot(projection="3d")
    ax.set_xlim(-1, 1), ax.set_ylim(-1, 1), ax.set_zlim(-1, 1)
    return fig, ax


# 1. Translucent and unfilled polygons hide nothing.


def test_a_line_under_a_translucent_surface_is_painted_under_it():
    """A red line under a blue alpha=0.3 plane: where the plane covers
    it, the picture is the plane over the line (0.3 blue + 0.7 red);
    beyond the plane, red."""
    fig, ax = _figure()
    _plane(ax, color="blue", alpha=0.3, shade=False, linewidth=0)
    t = np.linspace(-1.6, 1.6, 50)
    ax.plot(t, 0 * t, 0 * t - 0.5, color="red", linewidth=4)
    ax.set_xlim(-2, 2)
    ax.view_init(elev=90, azim=-90)  # from above: the plane covers x in [-1, 1]
    img = _png(fig, True)
    white = np.ones(3)
    under = 0.3 * (0.3 * BLUE + 0.7 * white) + 0.7 * RED  # line, then the plane over it
    r, c = _pixel(fig, ax, [[0.0, 0.0, -0.5], [0.5, 0.0, -0.5]])
    assert _near(img[r, c], 0.3 * BLUE + 0.7 * RED, 0.1).all() or _near(
        img[r, c], under, 0.1).all(), img[r, c]
    r, c = _pixel(fig, ax, [[1.5, 0.0, -0.5]])
    assert _near(img[r, c], RED, 0.1).all(), img[r, c]
    plt.close(fig)


def test_a_line_under_an_unfilled_surface_shows():
    """Under facecolor='none' polygons (edges only) the line is seen as
    matplotlib shows it: as many red pixels, give or take the edges."""
    fig, ax = _figure()
    _plane(ax, facecolor="none", edgecolor="k", linewidth=0.5)
    t = np.linspace(-0.9, 0.9, 50)
    ax.plot(t, 0.3 + 0 * t, 0 * t - 0.5, color="red", linewidth=3)
    plain = _near(_png(fig, False), RED).sum()
    bridged = _near(_png(fig, True), RED).sum()
    assert plain > 300 and bridged > 0.9 * plain, (plain, bridged)
    plt.close(fig)


# 2. axlim_clip


def test_axlim_clip_leaves_out_lines_and_quivers_outside_the_limits():
    fig, ax = _figure()
    Poly3DCollection([[(-1, -1, -1), (-0.8, -1, -1), (-1, -0.8, -1)]], facecolor="blue")
    ax.add_collection3d(Poly3DCollection([[(-1, -1, -1), (-0.8, -1, -1), (-1, -0.8, -1)]],
                                         facecolor="blue"))
    t = np.linspace(-2, 2, 81)
    ax.plot(t, 0 * t + 0.5, 0 * t, color="red", linewidth=3, axlim_clip=True)
    ax.quiver([0.0, 1.8], [-0.5, -0.5], [0.0, 0.0], [0.2, 0.2], [0, 0], [0, 0],
              color="red", linewidth=3, axlim_clip=True)
    img = _png(fig, True)
    r, c = _pixel(fig, ax, [[0.0, 0.5, 0.0], [0.05, -0.5, 0.0]])
    assert _near(img[r, c], RED, 0.2).all(), img[r, c]
    r, c = _pixel(fig, ax, [[1.6, 0.5, 0.0], [1.9, -0.5, 0.0]])
    assert not _near(img[r, c], RED, 0.3).any(), img[r, c]
    plt.close(fig)


# 3. closed=False


def test_an_open_polygon_has_no_closing_edge():
    """matplotlib's own picture is right for one polygon: the bridge's has
    as many black pixels (before: half again as many)."""
    fig, ax = _figure()
    square = np.array([[-0.8, -0.8, 0], [0.8, -0.8, 0], [0.8, 0.8, 0], [-0.8, 0.8, 0]])
    ax.add_collection3d(Poly3DCollection([square], closed=False, facecolor="none",
                                         edgecolor="k", linewidth=3))
    ax.set_axis_off()
    black = lambda img: (img.max(axis=-1) < 0.3).sum()  # noqa: E731
    plain, bridged = black(_png(fig, False)), black(_png(fig, True))
    assert plain > 200 and abs(bridged - plain) < 0.05 * plain, (plain, bridged)
    plt.close(fig)


# 4. Picking


def test_picking_works_after_a_bridged_draw():
    fig, ax = _figure()
    surf = _plane(ax, picker=True)
    line, = ax.plot([-1, 1], [0.5, 0.5], [0.5, 0.5], picker=True, pickradius=5)
    _png(fig, True)
    assert len(surf.get_paths()) == 25
    picked = []
    fig.canvas.mpl_connect("pick_event", lambda e: picked.append(e.artist))
    for artist, point in ((surf, [0.1, 0.1, 0.0]), (line, [0.0, 0.5, 0.5])):
        h = np.asarray(ax.M) @ np.array(point + [1.0])
        x, y = ax.transData.transform(h[:2] / h[3])
        event = MouseEvent("button_press_event", fig.canvas, x, y, button=1)
        assert artist.contains(event)[0], artist
        fig.pick(event)
        assert artist in picked, (artist, picked)
    plt.close(fig)


# 5. Per-collection attributes


def _crossing(ax, **kw):
    x = np.linspace(-1, 1, 8)
    X, Y = np.meshgrid(x, x)
    a = ax.plot_surface(X, Y, 0.5 * X, color="red", shade=False, **kw.get("a", {}))
    b = ax.plot_surface(X, Y, -0.5 * X, color="blue", shade=False, **kw.get("b", {}))
    return a, b


def _svg(fig) -> str:
    buf = io.StringIO()
    plytrace.mpl.savefig(fig, buf, format="svg")
    return buf.getvalue()


def test_each_collection_keeps_its_gid_and_rasterization():
    """Two crossing surfaces, cut into alternating runs: each run carries
    its own collection's gid (numbered after the first, ids being
    unique), and only the rasterized collection becomes images."""
    fig, ax = _figure()
    a, b = _crossing(ax, a={"gid": "first"}, b={"gid": "second"})
    b.set_label("blue plane")
    ids = re.findall(r'<g id="([^"]+)"', _svg(fig))
    assert "first" in ids and "second" in ids and "second-2" in ids, ids
    assert len(ids) == len(set(ids))
    for raster, vector in ((b, a), (a, b)):
        raster.set_rasterized(True)
        vector.set_rasterized(False)
        svg = _svg(fig)
        assert svg.count("<image") >= 2
        assert re.search(f'<g id="{vector.get_gid()}">\\s*<path', svg)
        assert f'<g id="{raster.get_gid()}"' not in svg  # as matplotlib's own
    assert ax.get_legend_handles_labels()[1] == ["blue plane"]
    plt.close(fig)


# 6. computed_zorder=False


def test_computed_zorder_off_keeps_the_users_order():
    """The user's zorder puts a plane over a surface: matplotlib's own
    picture is what was asked for, and the bridge's shows as much of it."""
    fig, ax = _figure()
    ax.computed_zorder = False
    x = np.linspace(-1, 1, 12)
    X, Y = np.meshgrid(x, x)
    ax.plot_surface(X, Y, 0.8 * np.sin(3 * X), color="red", shade=False, zorder=1)
    ax.plot_surface(X, Y, 0 * X, color="blue", shade=False, zorder=5)
    plain = _near(_png(fig, False), BLUE, 0.2).sum()
    bridged = _near(_png(fig, True), BLUE, 0.2).sum()
    # As many, or more (matplotlib leaves seams between the quads).
    assert plain > 5000 and 0.99 * plain < bridged < 1.1 * plain, (plain, bridged)
    plt.close(fig)


# 7. Pickling and copies


def test_a_fixed_figure_pickles_copies_and_draws_the_same():
    fig, ax = _figure()
    _crossing(ax)
    plytrace.mpl.fix(fig)
    want = _png(fig, False)  # fixed: drawn through the bridge
    for other in (pickle.loads(pickle.dumps(fig)), copy.deepcopy(fig)):
        (bx,) = other.axes
        assert plytrace.mpl.is_fixed(bx)
        assert np.array_equal(_png(other, False), want)
        plytrace.mpl.unfix(other)
        assert not plytrace.mpl.is_fixed(bx)
        plt.close(other)
    plt.close(fig)


# 8. Markers, text, patches, hatching, subfigures


def test_a_scatter_point_above_a_plane_is_seen_and_one_below_is_not():
    fig, ax = _figure()
    _plane(ax, color="blue", shade=False)
    ax.scatter([0.2, -0.2], [0.2, -0.2], [0.3, -0.3], color="red", s=80, depthshade=False)
    img = _png(fig, True)
    r, c = _pixel(fig, ax, [[0.2, 0.2, 0.3], [-0.2, -0.2, -0.3]])
    assert _near(img[r[0], c[0]], RED, 0.15), img[r[0], c[0]]
    assert _near(img[r[1], c[1]], BLUE, 0.15), img[r[1], c[1]]
    plt.close(fig)


def test_text_is_drawn_at_its_depth():
    fig, ax = _figure()
    _plane(ax, color="blue", shade=False)
    for z, word in ((0.3, "above"), (-0.3, "below")):
        ax.text(0, 0, z, "\u2588\u2588", color="red", fontsize=20, ha="center", va="center",
                gid=word)
    img = _png(fig, True)
    r, c = _pixel(fig, ax, [[0, 0, 0.3], [0, 0, -0.3]])
    assert _near(img[r[0], c[0]], RED, 0.15), img[r[0], c[0]]
    assert _near(img[r[1], c[1]], BLUE, 0.15), img[r[1], c[1]]
    plt.close(fig)


def test_a_patch_is_ordered_with_the_surfaces():
    """A disc on the floor seen through a gap in a plane above it shows,
    and the plane covers the rest of it."""
    from matplotlib.patches import Circle
    from mpl_toolkits.mplot3d import art3d

    fig, ax = _figure()
    x = np.linspace(-1, 1, 9)
    X, Y = np.meshgrid(x, x)
    Z = np.where((np.abs(X) < 0.3) & (np.abs(Y) < 0.3), np.nan, 0.3)
    ax.plot_surface(X, Y, Z, color="blue", shade=False)
    disc = Circle((0, 0), 0.8, color="red")
    ax.add_patch(disc)
    art3d.pathpatch_2d_to_3d(disc, z=-0.5)
    ax.view_init(elev=90, azim=-90)
    img = _png(fig, True)
    r, c = _pixel(fig, ax, [[0, 0, -0.5], [0.6, 0.0, -0.5]])
    assert _near(img[r[0], c[0]], RED, 0.15), img[r[0], c[0]]
    assert not _near(img[r[1], c[1]], RED, 0.3), img[r[1], c[1]]
    plt.close(fig)


def test_hatching_is_carried_over():
    fig, ax = _figure()
    _plane(ax, color="white", hatch="//", edgecolor="k", shade=False)
    buf = io.StringIO()
    plytrace.mpl.savefig(fig, buf, format="svg")
    assert "<pattern" in buf.getvalue()
    plt.close(fig)


def test_fix_takes_a_subfigure():
    fig = plt.figure(figsize=(6, 3))
    left, right = fig.subfigures(1, 2)
    ax = left.add_subplot(projection="3d")
    bx = right.add_subplot(projection="3d")
    _plane(ax)
    plytrace.mpl.fix(left)
    assert plytrace.mpl.is_fixed(ax) and not plytrace.mpl.is_fixed(bx)
    with plytrace.mpl.fixed(right):
        assert plytrace.mpl.is_fixed(bx)
    _png(fig, False)
    plt.close(fig)


# More of 1, 2, 5: polygons under translucent ones, axlim_clip of polygons
# and scatter, urls, clip paths and pickers of one collection among others,
# and matplotlib's own shading.


def test_a_translucent_plane_is_painted_over_a_line_and_a_plane_under_it():
    """From above: an opaque red plane, a green line over it, a blue
    alpha=0.5 plane over both. Each is seen through the blue: half blue,
    half what is under it."""
    fig, ax = _figure()
    _plane(ax, z=-0.5, color="red", shade=False)
    t = np.linspace(-0.8, 0.8, 40)
    ax.plot(t, 0 * t + 0.5, 0 * t - 0.25, color=(0, 1, 0), linewidth=5)
    _plane(ax, z=0.0, color="blue", alpha=0.5, shade=False, linewidth=0)
    ax.view_init(elev=90, azim=-90)
    img = _png(fig, True)
    green = np.array([0.0, 1.0, 0.0])
    r, c = _pixel(fig, ax, [[0.0, -0.5, -0.5], [0.0, 0.5, -0.25]])
    assert _near(img[r[0], c[0]], 0.5 * BLUE + 0.5 * RED, 0.08), img[r[0], c[0]]
    assert _near(img[r[1], c[1]], 0.5 * BLUE + 0.5 * green, 0.08), img[r[1], c[1]]
    plt.close(fig)


def test_axlim_clip_leaves_out_polygons_and_scatter_points_outside_the_limits():
    """Red quads and points, one of each within the limits and one
    reaching beyond them: with axlim_clip, what reaches beyond is left out
    (a polygon with a point outside goes whole, as matplotlib leaves it
    out), and matplotlib's own picture agrees."""
    fig, ax = _figure()
    quad = lambda x0, x1: [(x0, -0.9, 0), (x1, -0.9, 0), (x1, -0.5, 0), (x0, -0.5, 0)]  # noqa: E731
    ax.add_collection3d(Poly3DCollection([quad(-0.8, -0.4), quad(0.6, 1.4)], facecolor="red",
                                         axlim_clip=True))
    ax.scatter([-0.5, 1.5], [0.5, 0.5], [0.0, 0.0], color="red", s=120, depthshade=False,
               axlim_clip=True)
    ax.view_init(elev=90, azim=-90)
    r, c = _pixel(fig, ax, [[-0.6, -0.7, 0], [0.8, -0.7, 0], [-0.5, 0.5, 0], [1.5, 0.5, 0]])
    for bridge in (False, True):
        img = _png(fig, bridge)
        assert _near(img[r[0], c[0]], RED, 0.15) and _near(img[r[2], c[2]], RED, 0.15), bridge
        assert not _near(img[r[1], c[1]], RED, 0.3), (bridge, img[r[1], c[1]])
        assert not _near(img[r[3], c[3]], RED, 0.3), (bridge, img[r[3], c[3]])
    plt.close(fig)


def test_each_collection_keeps_its_url_clip_path_and_picker():
    """Two crossing surfaces, cut into alternating runs: each run links to
    its own collection's url; the blue one, clipped to the left half of
    the axes, shows only there while the red one shows in both halves;
    only the pickable one is picked."""
    from matplotlib.patches import Rectangle

    fig, ax = _figure()
    a, b = _crossing(ax)
    a.set_urls(["https://a.example/"])  # (a collection's links are per path)
    b.set_urls(["https://b.example/"])
    svg = _svg(fig)
    assert svg.count('xlink:href="https://a.example/"') >= 2, svg.count("a.example")
    assert svg.count('xlink:href="https://b.example/"') >= 2, svg.count("b.example")
    half = Rectangle((0, 0), 0.5, 1, transform=ax.transAxes)
    b.set_clip_path(half)
    img = _png(fig, True)
    x0, x1 = (ax.bbox.x0 * DPI / fig.dpi, ax.bbox.x1 * DPI / fig.dpi)
    mid = int((x0 + x1) / 2)
    blue, red = _near(img, BLUE, 0.25), _near(img, RED, 0.25)
    assert blue[:, :mid - 1].sum() > 500 and blue[:, mid + 1:].sum() == 0, blue.sum()
    assert red[:, :mid].sum() > 500 and red[:, mid:].sum() > 500
    a.set_picker(None)
    b.set_picker(True)
    picked = []
    fig.canvas.mpl_connect("pick_event", lambda e: picked.append(e.artist))
    h = np.asarray(ax.M) @ np.array([-0.5, 0.0, 0.0, 1.0])
    x, y = ax.transData.transform(h[:2] / h[3])
    fig.pick(MouseEvent("button_press_event", fig.canvas, x, y, button=1))
    assert picked == [b], picked
    plt.close(fig)


def test_each_face_keeps_its_own_url_and_colour():
    """A surface of 49 faces, each of its own colour and url, crossing a
    plane (so that its faces are drawn in runs between the plane's
    pieces): each link holds a path of its own face's colour, and every
    face's link is there."""
    fig, ax = _figure()
    x = np.linspace(-1, 1, 8)
    X, Y = np.meshgrid(x, x)
    rgb = np.random.default_rng(3).permutation(np.arange(49))
    colours = np.column_stack([0.2 + 0.01 * rgb, 1 - 0.01 * rgb, 0.5 + 0.005 * rgb,
                               np.ones(49)]).reshape(7, 7, 4)
    surf = ax.plot_surface(X, Y, 0.5 * X, facecolors=colours, shade=False, linewidth=0)
    ax.plot_surface(X, Y, -0.5 * X, color="gray", shade=False, linewidth=0)
    want = [matplotlib.colors.to_hex(c) for c in colours.reshape(49, 4)]  # the faces' order
    assert len(set(want)) == 49
    surf.set_urls([f"https://face{k}.example/" for k in range(49)])
    svg = _svg(fig)
    links = re.findall(r'<a xlink:href="https://face(\d+)\.example/"[^>]*>\s*'
                       r'<(?:use|path) [^>]*?fill: (#[0-9a-f]{6})', svg)
    assert sorted({int(k) for k, _ in links}) == list(range(49)), links
    runs = [g for g in svg.split('<g id="Poly3DCollection')[1:] if "face" in g.split("</g>")[0]]
    assert len(runs) >= 2, len(runs)  # drawn in runs between the plane's
    for k, fill in links:
        assert fill == want[int(k)], (k, fill, want[int(k)])
    plt.close(fig)


def test_shading_is_matplotlibs_own():
    """Two shaded surfaces side by side (one colormapped, one with a light
    source of its own) that hide nothing: the bridge paints matplotlib's
    colours (at the faces' centres the pictures agree)."""
    fig, ax = _figure()
    x = np.linspace(0.1, 1, 7)
    X, Y = np.meshgrid(x, x)
    ax.plot_surface(X, Y, 0.4 * np.sin(3 * X), cmap="viridis", shade=True, linewidth=0)
    ax.plot_surface(-X, -Y, 0.4 * np.cos(3 * Y), color="orange", shade=True, linewidth=0,
                    lightsource=matplotlib.colors.LightSource(30, 60))
    c = (x[:-1] + x[1:]) / 2
    cx, cy = (v.ravel() for v in np.meshgrid(c, c))
    plain, bridged = _png(fig, False), _png(fig, True)
    for xyz in ([cx, cy, 0.4 * np.sin(3 * cx)], [-cx, -cy, 0.4 * np.cos(3 * cy)]):
        r, col = _pixel(fig, ax, np.column_stack(xyz))
        assert len(np.unique(plain[r, col], axis=0)) > 5  # shaded, not flat
        diff = np.abs(plain[r, col] - bridged[r, col]).max(axis=-1)
        assert (diff < 0.02).all(), diff.max()
    plt.close(fig)
