"""A colormapped 100 x 100 plot_surface (9,801 quads) with a colorbar,
saved to SVG by matplotlib and through plytrace.mpl, three times each
after a first save that warms the caches:

    python python/benchmarks/mpl_surface_svg.py
"""

import os
import tempfile
import time

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import plytrace.mpl  # noqa: E402

x = np.linspace(-3, 3, 100)
X, Y = np.meshgrid(x, x)
Z = np.sin(X) * np.cos(Y) * np.exp(-0.1 * (X**2 + Y**2))
fig = plt.figure(figsize=(6, 5))
ax = fig.add_subplot(projection="3d")
surf = ax.plot_surface(X, Y, Z, cmap="viridis", rstride=1, cstride=1)
fig.colorbar(surf)
with tempfile.TemporaryDirectory() as d:
    plain, bridge = os.path.join(d, "plain.svg"), os.path.join(d, "bridge.svg")
    fig.savefig(plain)
    for _ in range(3):
        t = time.perf_counter()
        fig.savefig(plain)
        a = time.perf_counter() - t
        t = time.perf_counter()
        plytrace.mpl.savefig(fig, bridge)
        b = time.perf_counter() - t
        print(f"matplotlib {a:.3f} s, plytrace.mpl {b:.3f} s")
    print(f"SVG sizes: matplotlib {os.path.getsize(plain)} bytes, "
          f"plytrace.mpl {os.path.getsize(bridge)} bytes")
