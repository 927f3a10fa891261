"""The README's pictures: one matplotlib figure (a colormapped surface
crossed by a plane and by a line) saved by matplotlib alone and through
plytrace.mpl.

    python python/examples/mpl_side_by_side.py docs/images
"""

import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import plytrace.mpl  # noqa: E402

out = Path(sys.argv[1] if len(sys.argv) > 1 else ".")
x = np.linspace(-2, 2, 40)
X, Y = np.meshgrid(x, x)
fig = plt.figure(figsize=(4.2, 3.6))
ax = fig.add_subplot(projection="3d")
ax.plot_surface(X, Y, np.sin(1.5 * X) * np.cos(Y), cmap="viridis")
ax.plot_surface(X, Y, 0.4 * X - 0.2 * Y, color="tab:red", alpha=1.0)
t = np.linspace(-2, 2, 80)
ax.plot(t, 0.5 * t, 0.9 * np.cos(2 * t), color="black", linewidth=2)
fig.savefig(out / "mpl-plain.png", dpi=100)
plytrace.mpl.savefig(fig, out / "mpl-plytrace.png", dpi=100)
