"""Rotating a bridged figure: a 50 x 50 colormapped plot_surface with a 3-D
line through it, redrawn (Agg, fig.canvas.draw()) with the view changed
each time, by matplotlib alone and through plytrace.mpl; then a 100 x 100
surface saved to PNG both ways. Medians of the runs, in wall-clock time
and in CPU time of the process (all its threads: the bridge sorts in a
thread while matplotlib draws the axes):

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
    times, cpu = [], []
    for k in range(frames):
        ax.view_init(elev=30, azim=-60 + 7 * k)
        start, c = time.perf_counter(), time.process_time()
        fig.canvas.draw()
        times.append(time.perf_counter() - start)
        cpu.append(time.process_time() - c)
    plt.close(fig)
    return statistics.median(times), statistics.median(cpu)


def png_save(bridged, runs=5):
    x = np.linspace(-3, 3, 100)
    X, Y = np.meshgrid(x, x)
    fig = plt.figure(figsize=(6, 5), dpi=100)
    ax = fig.add_subplot(projection="3d")
    ax.plot_surface(X, Y, np.sin(X) * np.cos(Y), cmap="viridis", rstride=1, cstride=1)
    save = (lambda f: plytrace.mpl.savefig(fig, f, format="png")) if bridged else (
        lambda f: fig.savefig(f, format="png"))
    save(io.BytesIO())
    times, cpu = [], []
    for _ in range(runs):
        start, c = time.perf_counter(), time.process_time()
        save(io.BytesIO())
        times.append(time.perf_counter() - start)
        cpu.append(time.process_time() - c)
    plt.close(fig)
    return statistics.median(times), statistics.median(cpu)


frames = int(sys.argv[1]) if len(sys.argv) > 1 else 30
for bridged in (False, True):
    name = "plytrace.mpl" if bridged else "matplotlib"
    t, c = rotating(50, frames, bridged)
    print(f"{name:12} redraw of a 50 x 50 surface and a line: {t * 1000:6.1f} ms "
          f"({1 / t:5.1f} frames/s), CPU {c * 1000:6.1f} ms")
for bridged in (False, True):
    name = "plytrace.mpl" if bridged else "matplotlib"
    t, c = png_save(bridged)
    print(f"{name:12} PNG of a 100 x 100 surface: {t * 1000:6.1f} ms, CPU {c * 1000:6.1f} ms")
