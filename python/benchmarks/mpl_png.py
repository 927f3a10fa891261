"""PNG saves of several 3-D figures, by matplotlib alone and through
plytrace.mpl, interleaved save by save (so that a change in the machine's
load falls on both), with medians and spreads (min to max) of wall-clock
time and of the process's CPU time (all threads):

    python python/benchmarks/mpl_png.py [runs] [figure ...]

Figures: surface100 (a 100 x 100 colormapped plot_surface), surface50_line
(50 x 50 surface and a 3-D line), two_surfaces (two intersecting 60 x 60
surfaces), translucent (a translucent 60 x 60 surface over a scatter of
2,000 points), wireframe200 (a 200 x 200 plot_wireframe). Lines of the
form `name plain|bridge wall_ms cpu_ms` are printed per run with -v.
"""

import io
import statistics
import sys
import time

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import plytrace.mpl  # noqa: E402


def grid(n, r=3.0):
    x = np.linspace(-r, r, n)
    return np.meshgrid(x, x)


def surface100(ax):
    X, Y = grid(100)
    ax.plot_surface(X, Y, np.sin(X) * np.cos(Y), cmap="viridis", rstride=1, cstride=1)


def surface50_line(ax):
    X, Y = grid(50, 2.0)
    ax.plot_surface(X, Y, np.sin(1.5 * X) * np.cos(Y), cmap="viridis", rstride=1, cstride=1)
    t = np.linspace(-2, 2, 100)
    ax.plot(t, 0.5 * t, 0.9 * np.cos(2 * t), color="black", linewidth=2)


def two_surfaces(ax):
    X, Y = grid(60, 2.0)
    ax.plot_surface(X, Y, 0.5 * X, color="tab:blue", rstride=1, cstride=1)
    ax.plot_surface(X, Y, np.sin(X) * np.cos(Y), cmap="plasma", rstride=1, cstride=1)


def translucent(ax):
    X, Y = grid(60, 2.0)
    rng = np.random.default_rng(1)
    p = rng.uniform(-2, 2, (3, 2000))
    ax.scatter(p[0], p[1], p[2] * 0.5, c=p[2], s=6)
    ax.plot_surface(X, Y, np.sin(X) * np.cos(Y), cmap="viridis", alpha=0.5,
                    rstride=1, cstride=1)


def wireframe200(ax):
    X, Y = grid(200)
    ax.plot_wireframe(X, Y, np.sin(X) * np.cos(Y), rstride=1, cstride=1, linewidth=0.3)


FIGURES = {f.__name__: f for f in (surface100, surface50_line, two_surfaces, translucent,
                                   wireframe200)}


def figure(build):
    fig = plt.figure(figsize=(6, 5), dpi=100)
    build(fig.add_subplot(projection="3d"))
    return fig


def timed(save):
    start, c = time.perf_counter(), time.process_time()
    save(io.BytesIO())
    return time.perf_counter() - start, time.process_time() - c


def spread(xs):
    ms = [x * 1000 for x in xs]
    return f"{statistics.median(ms):6.1f} ({min(ms):5.1f}-{max(ms):5.1f})"


def bench(name, runs, verbose):
    fig = figure(FIGURES[name])
    saves = {"plain": lambda f: fig.savefig(f, format="png"),
             "bridge": lambda f: plytrace.mpl.savefig(fig, f, format="png")}
    for save in saves.values():
        save(io.BytesIO())
    got = {k: ([], []) for k in saves}
    for _ in range(runs):
        for k, save in saves.items():
            wall, cpu = timed(save)
            got[k][0].append(wall)
            got[k][1].append(cpu)
            if verbose:
                print(f"{name} {k} {wall * 1000:.1f} {cpu * 1000:.1f}")
    plt.close(fig)
    for k, label in (("plain", "matplotlib"), ("bridge", "plytrace.mpl")):
        wall, cpu = got[k]
        print(f"{name:15} {label:12} wall {spread(wall)} ms, CPU {spread(cpu)} ms")


args = [a for a in sys.argv[1:] if a != "-v"]
runs = int(args[0]) if args and args[0].isdigit() else 9
names = [a for a in args if not a.isdigit()] or list(FIGURES)
for n in names:
    bench(n, runs, "-v" in sys.argv)
