#!/usr/bin/env python3
"""Writes scenes/meshes/torus.obj: a torus with vertex normals and uvs, glint's own example mesh.

Usage: python3 scripts/make_torus.py [MAJOR_SEGMENTS MINOR_SEGMENTS]   (default 48 24)
Radii: 1 (ring) and 0.35 (tube); axis +y, centred at the origin.
"""
import math
import os
import sys

major_n, minor_n = (int(sys.argv[1]), int(sys.argv[2])) if len(sys.argv) == 3 else (48, 24)
R, r = 1.0, 0.35
lines = [f"# torus R={R} r={r}, {major_n}x{minor_n} segments, made by scripts/make_torus.py"]
for i in range(major_n + 1):
    u = 2 * math.pi * i / major_n
    for j in range(minor_n + 1):
        v = 2 * math.pi * j / minor_n
        nx, ny, nz = math.cos(v) * math.cos(u), math.sin(v), math.cos(v) * math.sin(u)
        cx, cz = R * math.cos(u), R * math.sin(u)
        lines.append(f"v {cx + r * nx:.6f} {r * ny:.6f} {cz + r * nz:.6f}")
        lines.append(f"vn {nx:.6f} {ny:.6f} {nz:.6f}")
        lines.append(f"vt {i / major_n:.6f} {j / minor_n:.6f}")
row = minor_n + 1
for i in range(major_n):
    for j in range(minor_n):
        a, b = i * row + j + 1, (i + 1) * row + j + 1
        c, d = b + 1, a + 1
        # Counter-clockwise seen from outside, so the winding normal points out.
        lines.append(f"f {a}/{a}/{a} {d}/{d}/{d} {c}/{c}/{c} {b}/{b}/{b}")
out = os.path.join(os.path.dirname(__file__), "..", "scenes", "meshes", "torus.obj")
with open(out, "w") as f:
    f.write("\n".join(lines) + "\n")
print(f"wrote {out}: {major_n * minor_n * 2} triangles")
