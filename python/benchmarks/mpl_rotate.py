"""Rotating a bridged figure: a 50 x 50 colormapped plot_surface with a 3-D
line through it, redrawn (Agg, fig.canvas.draw()) with the view changed
each time, by matplotlib alone and through plytrace.mpl; then a 100 x 100
surface saved to PNG both ways. Medians of the runs:

    python python/benchmarks/mpl_rotate.py [frames]
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


def rotating(n, frames, bridged):
    x = np.linspace(-2, 2, n)
    X, Y = np.meshgrid(x, x)
    fig = plt.figure(figsize=(6, 5), dpi=100)
    ax = fig.add_subplot(projection="3d")
    ax.plot_surface(X, Y, np.sin(1.5 * X) * np.cos(Y), cmap="viridis", rstride=1, cstride=1)
    t = np.linspace(-2, 2, 100)
    ax.plot(t, 0.5 * t, 0.9 * np.cos(2 * t), color="black", linewidth=2)
    if bridged:
        plytrace.mpl.fix(ax)
    fig.canvas.draw()
    times = []
    for k in range(frames):
        ax.view_init(elev=30, azim=-60 + 7 * k)
        start = time.perf_counter()
        fig.canvas.draw()
        times.append(time.perf_counter() - start)
    plt.close(fig)
    return statistics.median(times)


def png_save(bridged, runs=5):
    x = np.linspace(-3, 3, 100)
    X, Y = np.meshgrid(x, x)
    fig = plt.figure(figsize=(6, 5), dpi=100)
    ax = fig.add_subplot(projection="3d")
    ax.plot_surface(X, Y, np.sin(X) * np.cos(Y), cmap="viridis", rstride=1, cstride=1)
    save = (lambda f: plytrace.mpl.savefig(fig, f, format="png")) if bridged else (
        lambda f: fig.savefig(f, format="png"))
    save(io.BytesIO())
    times = []
    for _ in range(runs):
        start = time.perf_counter()
        save(io.BytesIO())
        times.append(time.perf_counter() - start)
    plt.close(fig)
    return statistics.median(times)


frames = int(sys.argv[1]) if len(sys.argv) > 1 else 30
for bridged in (False, True):
    name = "plytrace.mpl" if bridged else "matplotlib"
    t = rotating(50, frames, bridged)
    print(f"{name:12} redraw of a 50 x 50 surface and a line: {t * 1000:6.1f} ms "
          f"({1 / t:5.1f} frames/s)")
for bridged in (False, True):
    name = "plytrace.mpl" if bridged else "matplotlib"
    print(f"{name:12} PNG of a 100 x 100 surface: {png_save(bridged) * 1000:6.1f} ms")
