"""A closed mesh of 70,000 triangles (a torus) to SVG with
plytrace.render_vector: time the whole process, Python's start-up and
the imports included, with

    time python python/benchmarks/render_vector_70k.py out.svg
"""

import sys

import numpy as np

import plytrace

U, V = 250, 140  # 2 * U * V = 70,000 triangles
u = np.linspace(0, 2 * np.pi, U, endpoint=False)
v = np.linspace(0, 2 * np.pi, V, endpoint=False)
uu, vv = np.meshgrid(u, v, indexing="ij")
R, r = 1.0, 0.35
vertices = np.column_stack(
    [
        ((R + r * np.cos(vv)) * np.cos(uu)).ravel(),
        ((R + r * np.cos(vv)) * np.sin(uu)).ravel(),
        (r * np.sin(vv)).ravel(),
    ]
)
i, j = np.meshgrid(np.arange(U), np.arange(V), indexing="ij")
a = (i * V + j).ravel()
b = (((i + 1) % U) * V + j).ravel()
c = (((i + 1) % U) * V + (j + 1) % V).ravel()
d = (i * V + (j + 1) % V).ravel()
faces = np.concatenate([np.column_stack([a, b, c]), np.column_stack([a, c, d])])
assert len(faces) == 70_000
out = sys.argv[1] if len(sys.argv) > 1 else "torus70k.svg"
plytrace.render_vector(vertices, faces, path=out, material=plytrace.Material(color=(0.3, 0.6, 0.9)))
