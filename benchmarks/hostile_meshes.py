#!/usr/bin/env python3
"""How often glint's BVH closest hits disagree with Embree 4 (robust) on hostile meshes (issue 23).

Four families of meshes are generated with numpy (fixed seeds), each with rays whose answer is
either unambiguous or deliberately hard:

* `tiny`:  a closed blob (icosphere subdivided 3 times, radius 1e-4, vertices jittered by 1 %
           of the radius) hit by rays from distance 1 aimed at random points inside it;
* `far`:   the same blob with radius 25 centred at (1e5, -2e5, 3e5), rays from the world origin
           aimed at random points inside it;
* `thin`:  needle strips (two triangles, width 1e-3, 1e-4, 1e-5, length 1) seen from t = 2.5
           with rays aimed inside them; near-degenerate caps (height 1e-6 .. 1e-2 over a base of
           0.1); rays grazing the needles' planes (0 .. 1e-3 rad). Each needle and cap exists
           axis-aligned (exact coordinates) and turned by a random rotation (rounded ones);
* `grid`:  two overlapping coplanar grids and three closed boxes (one touching another), every
           coordinate a multiple of 1/16 (exact in f32); rays aimed at exact vertices and edge
           midpoints (axis-aligned, so exactly through them, and oblique), near-parallel rays
           over the grid, and rays skimming a box's top face at offsets 0 and +-2^-k.

Each family is written in the formats of the Embree anchor (../shared/anchors/embree/README.md)
that `glint bench-rays` reads: `<family>.ply` (binary PLY, faces in file order = prim ids),
`<family>.rays` (float32[N][8] = ox oy oz dx dy dz tmin tmax, |d| = 1, tmin = 0, tmax = +inf),
and `.hits` files ({float32 t, uint32 prim}, miss = (+inf, 0xFFFFFFFF)): `embree.hits` from
Embree with RTC_SCENE_FLAG_ROBUST (embreex, as the anchor's reference hits), `glint.hits` from
`glint bench-rays ... --out` (its stdout in `glint.log`). Beside them: `<family>.labels.npy`
(per ray: kind, must-hit, unambiguous, t-known, float64 answer) and `<family>.json`
(parameters, kinds, regions, checksums).

What "unambiguous" means: every ray is also traced in float64 against every triangle, on the
f32 values the tracers read. A ray's answer is unambiguous when it cannot change under errors
of ERR_ULPS (default 16) f32 ulps of the ray's coordinate magnitude (|o|max + |v|max): the
nearest triangle the ray could touch is hit with every edge at least that far from the ray
line (measured in the plane perpendicular to the ray, where watertight tests work), its t is
known to half the 1e-4 tolerance, and every other triangle the ray could touch is clearly
farther; or no triangle comes within that distance (a clear miss). Rays through a vertex,
along an edge, in a plane, or onto coplanar overlapping triangles are therefore ambiguous
(counted, not judged). "t known" is weaker: every triangle that could be the nearest hit lies
at the same t (both halves of a needle, a flat fan around a vertex), so a hit, whichever
triangle it names, must report that t.

"Must hit": the ray passes, by that same margin, through the interior of a closed part (the
blobs' inscribed ball, a box shrunk by the margin) or through a watertight open sheet inside
its outline (a needle strip, a cap, a grid): any watertight tracer has to report a hit there,
even when which triangle is hit is ambiguous.

Per family (and per kind of ray) it reports: rays; unambiguous rays; agreement with Embree in
the anchor's check_hits.py terms (`same` = same prim and t within 1e-4 relative, `equiv` =
other prim at the same t, then t_off / hit_miss / other); glint misses where Embree hits (and
the reverse); must-hit rays each tracer missed; and, against the float64 answer, each
tracer's wrong answers on unambiguous rays and its hits with a wrong t on t-known rays (so a
disagreement says who is wrong). glint runs on one thread, each query once.

Run (from /work/main; the venv lives outside the repository):

    python3 -m venv /tmp/venv-embree
    /tmp/venv-embree/bin/pip install -r ../shared/anchors/embree/requirements.txt
    /tmp/venv-embree/bin/python benchmarks/hostile_meshes.py --rays 4096 --json-out /tmp/hostile.json

Options: --out DIR (default: a new temporary folder), --glint PATH (default
target/release/glint; build it with `cargo build --release`), --families tiny far thin grid,
--rays N (per family, split over its kinds), --seed S, --err-ulps K, --json-out FILE,
--show N (print the first N rays per family where the float64 answer or a must-hit region
says glint is wrong). Files are byte-identical between runs with the same numpy/embreex versions.
"""
import argparse
import os
import platform
import subprocess
import sys
import tempfile
import time
import zlib

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
ANCHOR = os.path.join(ROOT, "..", "shared", "anchors", "embree")
sys.path.insert(0, ANCHOR)
import common  # noqa: E402  (the anchor's PLY writer, ray/hit file I/O, Embree scene build)
import check_hits  # noqa: E402  (the anchor's rules for comparing hits)

FAMILIES = ["tiny", "far", "thin", "grid"]
EPS32 = 2.0 ** -24  # unit roundoff of float32
REL_TOL = 1e-4  # t agreement, as check_hits.py and bench-rays use
MISS = np.uint32(0xFFFFFFFF)
# per ray: kind index (into <family>.json's "kinds"), the float64 labels, and the float64
# answer (prim: MISS unless unambiguous; t: +inf unless t_known)
LABEL_DTYPE = np.dtype([("kind", "<u2"), ("must_hit", "u1"), ("unambiguous", "u1"),
                        ("t_known", "u1"), ("f64_prim", "<u4"), ("f64_t", "<f8")])


def rng_for(seed, family):
    # Same scheme as the anchor's gen_rays.py: each family has its own stream, so adding a
    # family or changing one's ray count leaves the others' files unchanged.
    return np.random.Generator(np.random.PCG64([seed, zlib.crc32(f"hostile/{family}".encode())]))


def unit(v):
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def random_rotation(rng):
    q, r = np.linalg.qr(rng.normal(size=(3, 3)))
    q *= np.sign(np.diag(r))
    if np.linalg.det(q) < 0:
        q[:, 0] = -q[:, 0]
    return q


def split_counts(n, weights):
    """n rays over kinds in proportion to weights, every kind at least one ray."""
    w = np.asarray(weights, np.float64)
    c = np.maximum(1, np.floor(n * w / w.sum()).astype(int))
    c[np.argmax(w)] += max(0, n - c.sum())
    return c


def make_rays(origins, dirs):
    """float32 rays; the direction is normalised in float64 and rounded once, so |d| = 1 to an
    ulp and t is a distance, as in the anchor's sets."""
    rays = np.empty((len(origins), 8), np.float32)
    rays[:, 0:3] = origins
    rays[:, 3:6] = unit(np.asarray(dirs, np.float64))
    rays[:, 6] = 0.0  # embreex cannot pass tnear: every origin is well away from the surface
    rays[:, 7] = np.inf
    return rays


def aimed(targets, dirs, dist):
    """Rays that pass through `targets` at t = dist (before rounding to f32)."""
    d = unit(np.asarray(dirs, np.float64))
    return make_rays(targets - dist * d, d)


def cone_dirs(rng, axis, half_angle, n):
    """Uniform directions within half_angle of the unit vector axis (float64)."""
    cos_t = 1.0 - rng.random(n) * (1.0 - np.cos(half_angle))
    phi = rng.random(n) * 2 * np.pi
    axis = np.asarray(axis, np.float64)
    a = np.array([1.0, 0, 0]) if abs(axis[0]) < 0.9 else np.array([0, 1.0, 0])
    u = unit(np.cross(axis, a))
    v = np.cross(axis, u)
    sin_t = np.sqrt(1 - cos_t ** 2)
    return (cos_t[:, None] * axis + sin_t[:, None] * (np.cos(phi)[:, None] * u
                                                      + np.sin(phi)[:, None] * v))


class Builder:
    """Collects triangles and the regions rays must hit, in the order faces are written."""

    def __init__(self):
        self.verts, self.faces, self.regions = [], [], []
        self.nv = 0

    def add(self, verts, faces):
        base = self.nv
        self.verts.append(np.asarray(verts, np.float64))
        self.faces.append(np.asarray(faces, np.int64) + base)
        self.nv += len(verts)
        return base

    def arrays(self):
        return (np.concatenate(self.verts).astype(np.float32),
                np.concatenate(self.faces).astype(np.uint32))


# ------------------------------------------------------------------ geometry --

def icosphere(subdiv):
    """Unit icosphere, faces counter-clockwise seen from outside, vertices shared."""
    p = (1 + 5 ** 0.5) / 2
    v = [(-1, p, 0), (1, p, 0), (-1, -p, 0), (1, -p, 0), (0, -1, p), (0, 1, p), (0, -1, -p),
         (0, 1, -p), (p, 0, -1), (p, 0, 1), (-p, 0, -1), (-p, 0, 1)]
    f = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
         (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9),
         (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    v = [np.array(x, np.float64) / np.linalg.norm(x) for x in v]
    for _ in range(subdiv):
        mid, nf = {}, []

        def m(a, b):
            key = (min(a, b), max(a, b))
            if key not in mid:
                mid[key] = len(v)
                v.append(unit(v[a] + v[b]))
            return mid[key]
        for a, b, c in f:
            ab, bc, ca = m(a, b), m(b, c), m(c, a)
            nf += [(a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca)]
        f = nf
    return np.array(v), np.array(f, np.int64)


def blob(rng, centre, radius, jitter=0.01):
    """Jittered icosphere; returns f32 vertices, faces and the radius of a ball around the
    centre that is certainly inside: the least distance from the centre to a face's plane
    bounds the distance to every face, and the centre is inside (all faces face away from it)."""
    v, f = icosphere(3)
    v = v + rng.uniform(-jitter, jitter, v.shape)
    verts = (np.asarray(centre, np.float64) + radius * v).astype(np.float32)
    p = verts.astype(np.float64)[f]
    n = unit(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]))
    h = np.einsum("ij,ij->i", n, p[:, 0] - np.asarray(centre, np.float64))
    assert np.all(h > 0), "a face of the blob faces its centre"
    return verts, f, float(h.min())


def blob_family(rng, n, centre, radius, origin_of):
    """Shared by tiny and far: rays from origin_of(rng, n) aimed at uniform points of the
    inscribed ball (all must hit; which face is hit is random, so many land near edges)."""
    b = Builder()
    verts, faces, r_in = blob(rng, centre, radius)
    b.add(verts.astype(np.float64), faces)
    b.regions.append(("ball", np.asarray(centre, np.float64), r_in))
    s = unit(rng.normal(size=(n, 3)))
    targets = np.asarray(centre) + 0.95 * r_in * s * rng.random((n, 1)) ** (1 / 3)
    origins = origin_of(rng, n)
    rays = make_rays(origins, targets - origins)
    return b, [("interior", rays)], {"centre": list(centre), "radius": radius,
                                     "inscribed_radius": r_in, "subdivisions": 3, "jitter": 0.01}


def family_tiny(rng, n):
    c = (0.0, 0.0, 0.0)
    return blob_family(rng, n, c, 1e-4,
                       lambda rng, n: np.asarray(c) + unit(rng.normal(size=(n, 3))))


def family_far(rng, n):
    return blob_family(rng, n, (1e5, -2e5, 3e5), 25.0, lambda rng, n: np.zeros((n, 3)))


def family_thin(rng, n):
    b = Builder()
    widths = [1e-3, 1e-4, 1e-5]
    heights = [1e-6, 1e-5, 1e-4, 1e-3, 1e-2]
    rot = random_rotation(rng)
    placements = {  # axis-aligned: exact coordinates; rotated: every coordinate rounded
        "axis": lambda p: p,
        "rot": lambda p: (np.asarray(p) - [0.5, 0.5, 0]) @ rot.T + [0.5, 0.5, 1.5],
    }
    needles, caps = [], []  # (label, corners as written in f32)
    for pname, place in placements.items():
        for k, w in enumerate(widths):
            y0 = 0.25 * k
            quad = place(np.array([[0, y0, 0], [1, y0, 0], [1, y0 + w, 0], [0, y0 + w, 0.0]]))
            b.add(quad, [(0, 1, 2), (0, 2, 3)])  # both share the long diagonal 0-2
            q32 = quad.astype(np.float32).astype(np.float64)  # as written to the file
            b.regions.append(("polygon", q32))
            needles.append((f"needle w={w:.0e} {pname}", q32))
        for k, h in enumerate(heights):
            y0 = 0.1 + 0.25 * k
            tri = place(np.array([[1.5, y0, 0], [1.6, y0, 0], [1.55, y0 + h, 0.0]]))
            b.add(tri, [(0, 1, 2)])
            t32 = tri.astype(np.float32).astype(np.float64)
            b.regions.append(("polygon", t32))
            caps.append((f"cap h={h:.0e} {pname}", t32))
    angles = [0.0, 1e-7, 1e-6, 1e-5, 1e-4, 1e-3]

    def plane_normal(p):
        return unit(np.cross(p[1] - p[0], p[2] - p[0]))

    def inside_quad(q, m):
        s, r = rng.random((m, 1)), rng.random((m, 1))
        return q[0] + s * (q[1] - q[0]) + r * (q[3] - q[0])

    def inside_tri(t, m):
        u, v = rng.random((m, 1)), rng.random((m, 1))
        flip = (u + v) > 1
        u, v = np.where(flip, 1 - u, u), np.where(flip, 1 - v, v)
        return t[0] + u * (t[1] - t[0]) + v * (t[2] - t[0])

    def both_sides(nrm, m):
        # up to 60 degrees off the normal, from either side
        return cone_dirs(rng, nrm, np.radians(60), m) * rng.choice([-1.0, 1.0], (m, 1))

    kinds = [(lab, "needle", q) for lab, q in needles] + [(lab, "cap", t) for lab, t in caps]
    kinds += [(f"graze a={a:.0e}", "graze", a) for a in angles]
    weights = [3.0 if k[1] == "needle" else 1.0 for k in kinds]
    sets = []
    for (label, what, geo), m in zip(kinds, split_counts(n, weights)):
        if what == "needle":
            rays = aimed(inside_quad(geo, m), both_sides(plane_normal(geo), m), 2.5)
        elif what == "cap":
            rays = aimed(inside_tri(geo, m), both_sides(plane_normal(geo), m), 2.5)
        else:  # grazing: in-plane heading (any azimuth) tilted by `geo` radians off the plane
            pick = rng.integers(0, len(needles), m)
            targets, dirs = np.empty((m, 3)), np.empty((m, 3))
            for i, j in enumerate(pick):
                q = needles[j][1]
                nrm = plane_normal(q)
                e1 = unit(q[1] - q[0])
                e2 = np.cross(nrm, e1)
                phi = rng.random() * 2 * np.pi
                heading = np.cos(phi) * e1 + np.sin(phi) * e2
                targets[i] = inside_quad(q, 1)[0]
                dirs[i] = np.cos(geo) * heading + np.sin(geo) * nrm * rng.choice([-1.0, 1.0])
            rays = aimed(targets, dirs, 2.5)
        sets.append((label, rays))
    return b, sets, {"widths": widths, "cap_heights": heights, "cap_base": 0.1,
                     "graze_angles_rad": angles, "rotation": rot.tolist(), "distance": 2.5}


def grid_sheet(b, x0, y0, nx, ny, hx, hy, z):
    """nx x ny cells in the plane z, diagonals alternating so vertices join 4 or 8 triangles."""
    ii, jj = np.meshgrid(np.arange(nx + 1), np.arange(ny + 1), indexing="ij")
    verts = np.stack([x0 + ii.ravel() * hx, y0 + jj.ravel() * hy, np.full(ii.size, z)], 1)
    faces = []
    for i in range(nx):
        for j in range(ny):
            a, bb, c, d = (i * (ny + 1) + j, (i + 1) * (ny + 1) + j, (i + 1) * (ny + 1) + j + 1,
                           i * (ny + 1) + j + 1)
            faces += [(a, bb, c), (a, c, d)] if (i + j) % 2 == 0 else [(a, bb, d), (bb, c, d)]
    base = b.add(verts, faces)
    b.regions.append(("polygon", np.array([[x0, y0, z], [x0 + nx * hx, y0, z],
                                           [x0 + nx * hx, y0 + ny * hy, z], [x0, y0 + ny * hy, z]])))
    return verts, np.asarray(faces) + base


def grid_box(b, lo, hi, n):
    """Closed axis-aligned box, every face an n x n grid, outward-facing, vertices shared."""
    lo, hi = np.asarray(lo, np.float64), np.asarray(hi, np.float64)
    index, verts, faces = {}, [], []

    def vid(p):
        key = tuple(p)
        if key not in index:
            index[key] = len(verts)
            verts.append(p)
        return index[key]
    for axis in range(3):
        u, v = (axis + 1) % 3, (axis + 2) % 3  # (u, v, axis) is right-handed
        for side, sign in ((lo[axis], -1), (hi[axis], 1)):
            for i in range(n):
                for j in range(n):
                    quad = []
                    for di, dj in ((0, 0), (1, 0), (1, 1), (0, 1)):
                        p = np.zeros(3)
                        p[axis] = side
                        p[u] = lo[u] + (hi[u] - lo[u]) * (i + di) / n
                        p[v] = lo[v] + (hi[v] - lo[v]) * (j + dj) / n
                        quad.append(vid(p))
                    a, bb, c, d = quad if sign > 0 else quad[::-1]
                    faces += [(a, bb, c), (a, c, d)]
    base = b.add(np.array(verts), faces)
    b.regions.append(("box", lo, hi))
    return np.array(verts), np.asarray(faces) + base


def edge_midpoints(verts, faces):
    e = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    e = np.unique(np.sort(e, axis=1), axis=0)
    return 0.5 * (verts[e[:, 0]] + verts[e[:, 1]])


def family_grid(rng, n):
    b = Builder()
    # Grid B overlaps half of grid A in the same plane with other cells: z-fighting, where
    # which prim is hit is a coin toss but a hit is certain.
    sheets = [grid_sheet(b, 0.0, 0.0, 16, 16, 1 / 16, 1 / 16, 0.0),
              grid_sheet(b, 0.5, 1 / 32, 8, 16, 1 / 8, 1 / 16, 0.0)]
    boxes = [grid_box(b, (2, 0, 0), (3, 1, 1), 4),
             grid_box(b, (3, 0, 0), (3.5, 0.5, 0.5), 1),  # touches box 1's face x = 3
             grid_box(b, (4, 0, 0), (4 + 1 / 16, 1 / 16, 1 / 16), 1)]
    all_v = np.concatenate(b.verts)
    grid_vertices = np.concatenate([all_v[np.unique(f)] for _, f in sheets])
    grid_mids = np.concatenate([edge_midpoints(all_v, f) for _, f in sheets])
    box_specs = [(r[1], r[2]) for r in b.regions if r[0] == "box"]
    box_corners = np.array([[x, y, z] for lo, hi in box_specs
                            for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])])
    box_mids = np.concatenate([edge_midpoints(all_v, f) for _, f in boxes])
    box_face_vertices = np.concatenate([v for v, _ in boxes])

    def pick(points, m):
        return points[rng.integers(0, len(points), m)]

    def vertical(m):  # exactly +-z: origin and target differ only in z, both exact
        return np.array([0, 0, 1.0]) * rng.choice([-1.0, 1.0], (m, 1))

    def oblique(m):
        return cone_dirs(rng, [0, 0, 1.0], np.radians(70), m) * rng.choice([-1.0, 1.0], (m, 1))

    def into_box(points):
        # Aim from a boundary point towards a random point well inside the box holding it:
        # the box is convex, so the ray enters exactly there and crosses the interior.
        d = np.empty_like(points)
        for i, p in enumerate(points):
            lo, hi = next((lo, hi) for lo, hi in box_specs if np.all(p >= lo) and np.all(p <= hi))
            q = lo + (0.1 + 0.8 * rng.random(3)) * (hi - lo)
            d[i] = q - p
        return d

    def axis_into_face(points):
        # exact -outward normal of a face the point lies on
        d = np.zeros_like(points)
        for i, p in enumerate(points):
            lo, hi = next((lo, hi) for lo, hi in box_specs if np.all(p >= lo) and np.all(p <= hi))
            faces_on = [(a, s) for a in range(3) for s, c in ((-1, lo[a]), (1, hi[a])) if p[a] == c]
            a, s = faces_on[rng.integers(0, len(faces_on))]
            d[i, a] = -s
        return d

    def parallel(a):
        def rays(m):
            # in-plane heading, tilted a radians off grid A's plane; a = 0 lies in it exactly
            phi = rng.random(m) * 2 * np.pi
            up = rng.choice([-1.0, 1.0], m)
            d = np.stack([np.cos(a) * np.cos(phi), np.cos(a) * np.sin(phi), up * np.sin(a)], 1)
            # half at exact vertices of grid A, half at random points of it
            t = np.where(rng.random((m, 1)) < 0.5, pick(sheets[0][0], m),
                         np.c_[rng.random((m, 2)), np.zeros(m)])
            return aimed(t, d, 2.0)
        return rays

    def skim(dz):
        def rays(m):
            # along +x at height 1 + dz, over box 1's top face (z = 1) and onto its face x = 2;
            # dz = 0 runs in the top face's plane onto the edge between the two faces
            o = np.stack([np.full(m, 1.75), 0.05 + 0.9 * rng.random(m), np.full(m, 1.0 + dz)], 1)
            return make_rays(o, np.tile([1.0, 0, 0], (m, 1)))
        return rays

    parallel_angles = [0.0, 1e-6, 1e-4, 1e-2]
    skim_offsets = [0.0] + [s * 2.0 ** -k for k in (22, 16, 10, 4) for s in (1, -1)]
    kinds = [  # (label, weight, rays(m))
        ("grid vertex axis", 2, lambda m: aimed(pick(grid_vertices, m), vertical(m), 2.0)),
        ("grid vertex oblique", 2, lambda m: aimed(pick(grid_vertices, m), oblique(m), 2.0)),
        ("grid edge-mid axis", 2, lambda m: aimed(pick(grid_mids, m), vertical(m), 2.0)),
        ("grid edge-mid oblique", 2, lambda m: aimed(pick(grid_mids, m), oblique(m), 2.0)),
        ("box corner", 1.5, lambda m: (lambda p: aimed(p, into_box(p), 2.0))(pick(box_corners, m))),
        ("box edge-mid", 1.5, lambda m: (lambda p: aimed(p, into_box(p), 2.0))(pick(box_mids, m))),
        ("box face-vertex axis", 1.5,
         lambda m: (lambda p: aimed(p, axis_into_face(p), 2.0))(pick(box_face_vertices, m))),
    ]
    kinds += [(f"grid parallel a={a:.0e}", 0.6, parallel(a)) for a in parallel_angles]
    kinds += [(f"box skim dz={dz:+.1e}", 0.3, skim(dz)) for dz in skim_offsets]
    sets = [(label, make(m)) for (label, _, make), m in
            zip(kinds, split_counts(n, [w for _, w, _ in kinds]))]
    boxes_json = [[lo.tolist(), hi.tolist()] for lo, hi in box_specs]
    return b, sets, {"cell": "1/16", "sheets": 2, "boxes": boxes_json,
                     "parallel_angles_rad": parallel_angles, "skim_offsets": skim_offsets}


GENERATORS = {"tiny": family_tiny, "far": family_far, "thin": family_thin, "grid": family_grid}


def is_closed(faces):
    """Every directed edge appears once and its reverse once: closed and consistently oriented."""
    e = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]]).astype(np.int64)
    key = e[:, 0] * (faces.max() + 1) + e[:, 1]
    rkey = e[:, 1] * (faces.max() + 1) + e[:, 0]
    return bool(len(np.unique(key)) == len(key) and np.all(np.isin(rkey, key)))


# ------------------------------------------------------- float64 ground truth --

def trip_over_len(o, d, a, b):
    """Signed distance, in the plane perpendicular to d, from the ray to the line a-b:
    d.((a-o) x (b-o)) / |d x (b-a)| (0 when the edge is parallel to the ray). Its sign is the
    edge test of a watertight intersector; its size is how far rounding must move the ray."""
    tr = np.sum(d * np.cross(a - o, b - o), axis=-1)
    ln = np.linalg.norm(np.cross(d, b - a), axis=-1)
    return np.divide(tr, ln, out=np.zeros_like(tr), where=ln > 0)


def error_scale(rays, verts, err_ulps):
    """Per ray, how far an f32 tracer's rounding can move it relative to the triangles:
    err_ulps f32 ulps of the largest coordinate it meets (origin and mesh, as the watertight
    test subtracts the origin from every vertex)."""
    return err_ulps * EPS32 * (np.abs(rays[:, 0:3]).max(1).astype(np.float64)
                               + np.abs(verts).max())


def narrow(lo, hi):
    """An interval of t that two correct tracers cannot turn into a 1e-4 disagreement."""
    return hi - lo <= 0.5 * REL_TOL * np.abs(lo)


def f64_answers(rays, verts, faces, delta, err_ulps, chunk_pairs=200_000):
    """Every ray against every triangle in float64. Returns per ray
    (unambiguous, prim, t_known, t): `unambiguous` and `prim` as the module docstring says
    (prim = MISS for a clear miss or an ambiguous ray); `t_known`: every triangle that could
    be the nearest hit lies at the same t (one triangle, a vertex of a flat fan, both halves
    of a needle, coplanar overlaps), so a hit, if any, must be at `t`."""
    o = rays[:, 0:3].astype(np.float64)
    d = rays[:, 3:6].astype(np.float64)
    p = verts.astype(np.float64)[faces.astype(np.int64)]
    n = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    nlen = np.linalg.norm(n, axis=1)
    assert np.all(nlen > 0), "zero-area triangle"
    nr = len(rays)
    unamb, t_known = np.zeros(nr, bool), np.zeros(nr, bool)
    prim = np.full(nr, MISS, np.uint32)
    tt = np.full(nr, np.inf)
    step = max(1, chunk_pairs // len(faces))
    for s in range(0, nr, step):
        sl = slice(s, s + step)
        ob, db, dl = o[sl, None, :], d[sl, None, :], delta[sl, None]
        with np.errstate(divide="ignore", invalid="ignore"):
            dn = db[:, 0, :] @ n.T  # d . normal, per ray and triangle
            # the three edge tests share the sign of d . n exactly when the line crosses
            sgn = np.where(dn >= 0, 1.0, -1.0)
            m = np.minimum.reduce([sgn * trip_over_len(ob, db, p[:, i], p[:, (i + 1) % 3])
                                   for i in range(3)])
            t = np.sum((p[:, 0] - ob) * n, axis=-1) / dn
            # how far t can move: the edge margin along a slanted plane, plus t's own rounding
            sig = dl / (np.abs(dn) / nlen) + err_ulps * EPS32 * np.abs(t)
            # a ray (nearly) in a triangle's plane has no usable t: any t is possible
            unknown = ~np.isfinite(t) | ~np.isfinite(sig)
            t_lo = np.where(unknown, -np.inf, t - sig)
            t_hi = np.where(unknown, np.inf, t + sig)
            possible = (m > -dl) & (t_hi > 0)
            sure = (m > dl) & (t_lo > 0) & ~unknown
        r = np.arange(len(dn))
        lo = np.where(possible, t_lo, np.inf)
        c1 = np.argmin(lo, axis=1)  # the candidate that could be nearest
        any_possible = possible.any(1)
        lo[r, c1] = np.inf
        second = lo.min(1)  # the nearest any other candidate could be
        hit = (any_possible & sure[r, c1] & narrow(t_lo[r, c1], t_hi[r, c1])
               & (second > t_hi[r, c1]))
        unamb[sl] = hit | ~any_possible
        prim[sl] = np.where(hit, c1, MISS)
        # t alone: the candidates that could come before the nearest sure hit (all of them if
        # none is sure) span less than the tolerance, so any hit reported must be at that t
        bound = np.where(sure, t_hi, np.inf).min(1)
        near = possible & (t_lo <= bound[:, None])
        n_lo = np.where(near, t_lo, np.inf).min(1)
        n_hi = np.where(near, t_hi, -np.inf).max(1)
        with np.errstate(invalid="ignore"):
            known = np.isfinite(n_lo) & np.isfinite(n_hi) & (n_lo > 0) & narrow(n_lo, n_hi)
            tt[sl] = np.where(known, 0.5 * (n_lo + n_hi), np.inf)
        t_known[sl] = known
    return unamb, prim, t_known, tt


def must_hit(rays, regions, delta):
    """Rays that cross a closed part's interior, or a watertight sheet inside its outline, by at
    least delta (see the module docstring)."""
    o = rays[:, 0:3].astype(np.float64)
    d = rays[:, 3:6].astype(np.float64)
    out = np.zeros(len(rays), bool)
    for reg in regions:
        if reg[0] == "ball":  # origin outside, line through the ball shrunk by delta, ahead
            _, c, r = reg
            oc = c - o
            # |d| is 1 only to an f32 ulp, and |oc|^2 - tc^2 cancels down to dist^2 << 1e-7
            tc = np.einsum("ij,ij->i", oc, unit(d))
            dist = np.sqrt(np.maximum(0, np.einsum("ij,ij->i", oc, oc) - tc ** 2))
            out |= (tc > 0) & (dist < r - delta) & (np.linalg.norm(oc, axis=1) > r)
        elif reg[0] == "box":  # slab test against the box shrunk by delta, exit ahead
            _, lo, hi = reg
            t0, t1 = np.full(len(o), -np.inf), np.full(len(o), np.inf)
            for a in range(3):
                l, h = lo[a] + delta, hi[a] - delta
                with np.errstate(divide="ignore", invalid="ignore"):
                    ta, tb = (l - o[:, a]) / d[:, a], (h - o[:, a]) / d[:, a]
                par = d[:, a] == 0
                inside = (o[:, a] > l) & (o[:, a] < h)
                t0 = np.where(par, np.where(inside, t0, np.inf), np.maximum(t0, np.minimum(ta, tb)))
                t1 = np.where(par, np.where(inside, t1, -np.inf), np.minimum(t1, np.maximum(ta, tb)))
            out |= (t0 < t1) & (t1 > 0)
        else:  # convex planar outline: inside every edge by delta, crossing ahead
            q = reg[1]
            s = np.stack([trip_over_len(o, d, q[i], q[(i + 1) % len(q)]) for i in range(len(q))])
            nrm = np.cross(q[1] - q[0], q[2] - q[0])
            with np.errstate(divide="ignore", invalid="ignore"):
                tc = ((q[0] - o) @ nrm) / (d @ nrm)
            out |= ((s.min(0) > delta) | (s.max(0) < -delta)) & (tc > 0)
    return out


# ------------------------------------------------------------------- tracers --

def run_glint(glint, mesh, rays, ref_hits, out_hits, log):
    cmd = [glint, "bench-rays", mesh, rays, "--hits", ref_hits, "--out", out_hits,
           "--threads", "1", "--repeat", "1"]
    print("$", " ".join(cmd), file=sys.stderr, flush=True)
    res = subprocess.run(cmd, capture_output=True, text=True)
    with open(log, "w") as f:
        f.write("$ " + " ".join(cmd) + "\n" + res.stdout + res.stderr)
    if res.returncode != 0:
        raise SystemExit(f"glint bench-rays failed ({res.returncode}):\n{res.stderr}")
    last = res.stdout.strip().splitlines()[-1]
    return dict(kv.split("=", 1) for kv in last.split()), res.stdout


def wrong_vs_f64(h, truth):
    """Rays whose answer in `h` (a .hits record array) the float64 answer contradicts:
    (unambiguous: other prim, hit/miss, or t beyond 1e-4; t_known: a hit t beyond 1e-4)."""
    with np.errstate(invalid="ignore"):
        t_bad = ~(np.abs(h["t"].astype(np.float64) - truth["t"]) <= REL_TOL * truth["t"])
    unamb = truth["unambiguous"] & ((h["prim"] != truth["prim"])
                                    | ((truth["prim"] != MISS) & t_bad))
    t_wrong = truth["t_known"] & (h["prim"] != MISS) & t_bad
    return unamb, t_wrong


def summarise(ref, cand, truth):
    """Counts for one set of rays (ref = Embree, cand = glint, both .hits records; truth =
    the float64 labels of the same rays)."""
    res, _ = check_hits.compare(ref, cand, REL_TOL, 0.0)
    rh, ch = ref["prim"] != MISS, cand["prim"] != MISS
    unamb, must = truth["unambiguous"], truth["must_hit"]
    u_res = check_hits.compare(ref[unamb], cand[unamb], REL_TOL, 0.0)[0] if unamb.any() else None
    g_wrong, g_t_wrong = wrong_vs_f64(cand, truth)
    e_wrong, e_t_wrong = wrong_vs_f64(ref, truth)
    return {"rays": res["n"], "unambiguous": int(unamb.sum()), "must_hit": int(must.sum()),
            "t_known": int(truth["t_known"].sum()),
            "embree_hits": res["ref_hits"], "glint_hits": res["cand_hits"],
            "same": res["same"], "equiv": res["equiv"], "t_off": res["t_off"],
            "hit_miss": res["hit_miss"], "other": res["other"],
            "same_on_unambiguous": u_res["same"] if u_res else 0,
            "glint_miss_embree_hit": int((rh & ~ch).sum()),
            "embree_miss_glint_hit": int((~rh & ch).sum()),
            "must_hit_missed_glint": int((must & ~ch).sum()),
            "must_hit_missed_embree": int((must & ~rh).sum()),
            "unambiguous_wrong_glint": int(g_wrong.sum()),
            "unambiguous_wrong_embree": int(e_wrong.sum()),
            "t_known_wrong_glint": int(g_t_wrong.sum()),
            "t_known_wrong_embree": int(e_t_wrong.sum())}


def sha256(path):
    return common.sha256_file(path)


# ---------------------------------------------------------------------- main --

def run_family(name, a, out_dir):
    rng = rng_for(a.seed, name)
    builder, sets, params = GENERATORS[name](rng, a.rays)
    verts, faces = builder.arrays()
    rays = np.concatenate([r for _, r in sets])
    kind = np.concatenate([np.full(len(r), i, np.uint16) for i, (_, r) in enumerate(sets)])
    kinds = [k for k, _ in sets]
    closed = is_closed(faces)

    d = os.path.join(out_dir, name)
    os.makedirs(d, exist_ok=True)
    mesh_p, rays_p = os.path.join(d, name + ".ply"), os.path.join(d, name + ".rays")
    emb_p, gl_p = os.path.join(d, "embree.hits"), os.path.join(d, "glint.hits")
    common.write_ply(mesh_p, verts, faces, comments=[f"glint hostile_meshes.py family {name} "
                                                     f"seed {a.seed}"])
    common.save_rays(rays_p, rays)

    t0 = time.perf_counter()
    delta = error_scale(rays, verts, a.err_ulps)
    must = must_hit(rays, builder.regions, delta)
    unamb, f64_prim, t_known, f64_t = f64_answers(rays, verts, faces, delta, a.err_ulps)
    t_f64 = time.perf_counter() - t0
    # A must-hit ray the float64 tracer clearly misses would mean the labels are wrong.
    contradictions = int((must & unamb & (f64_prim == MISS)).sum())
    if contradictions:
        print(f"warning: {name}: {contradictions} must-hit rays miss in float64", file=sys.stderr)

    scene = common.build_scene(verts, faces, robust=True)[0]
    common.save_hits(emb_p, *common.trace_closest(scene, rays))
    del scene
    glint_kv, glint_out = run_glint(a.glint, mesh_p, rays_p, emb_p, gl_p, os.path.join(d, "glint.log"))

    labels = np.zeros(len(rays), LABEL_DTYPE)
    labels["kind"], labels["must_hit"], labels["unambiguous"] = kind, must, unamb
    labels["t_known"], labels["f64_prim"], labels["f64_t"] = t_known, f64_prim, f64_t
    np.save(os.path.join(d, name + ".labels.npy"), labels)
    truth = {"unambiguous": unamb, "must_hit": must, "t_known": t_known, "prim": f64_prim,
             "t": f64_t}

    ref, cand = common.load_hits(emb_p), common.load_hits(gl_p)
    if len(cand) != len(rays):
        raise SystemExit(f"{gl_p}: {len(cand)} hits for {len(rays)} rays")
    total = summarise(ref, cand, truth)
    # bench-rays compares with the same rules; if its count differs, one of the two readers is off
    if glint_kv.get("matches") != f"{total['same'] + total['equiv']}/{len(rays)}":
        print(f"warning: {name}: bench-rays says matches={glint_kv.get('matches')}, this script "
              f"{total['same'] + total['equiv']}/{len(rays)}", file=sys.stderr)
    per_kind = {k: summarise(ref[kind == i], cand[kind == i],
                             {key: v[kind == i] for key, v in truth.items()})
                for i, k in enumerate(kinds)}

    # the first rays where the float64 answer or a must-hit region says glint is wrong
    g_wrong, g_t_wrong = wrong_vs_f64(cand, truth)
    bad = np.nonzero(g_wrong | g_t_wrong | (must & (cand["prim"] == MISS)))[0]
    examples = [{"ray": int(i), "kind": kinds[kind[i]], "origin": rays[i, :3].tolist(),
                 "dir": rays[i, 3:6].tolist(), "must_hit": bool(must[i]),
                 "unambiguous": bool(unamb[i]), "t_known": bool(t_known[i]),
                 "f64": [float(f64_t[i]), int(f64_prim[i])],
                 "embree": [float(ref["t"][i]), int(ref["prim"][i])],
                 "glint": [float(cand["t"][i]), int(cand["prim"][i])]} for i in bad[:a.show]]

    meta = {"family": name, "seed": a.seed, "closed": closed, "triangles": int(len(faces)),
            "vertices": int(len(verts)), "params": params, "kinds": kinds,
            "err_ulps": a.err_ulps, "f64_seconds": t_f64, "f64_contradictions": contradictions,
            "regions": [[r[0]] + [np.asarray(x).tolist() if not np.isscalar(x) else x
                                  for x in r[1:]] for r in builder.regions],
            "files": {"mesh": os.path.basename(mesh_p), "rays": os.path.basename(rays_p),
                      "embree_hits": "embree.hits", "glint_hits": "glint.hits",
                      "labels": name + ".labels.npy"},
            "sha256": {"mesh": sha256(mesh_p), "rays": sha256(rays_p),
                       "embree_hits": sha256(emb_p), "glint_hits": sha256(gl_p)},
            "labels_dtype": str(LABEL_DTYPE.descr),
            "glint_bench_rays": glint_kv, "glint_stdout": glint_out.splitlines()}
    common.write_json(os.path.join(d, name + ".json"), meta)
    return {"family": name, "closed": closed, "triangles": int(len(faces)), **total,
            "per_kind": per_kind, "examples": examples, "f64_contradictions": contradictions}


COLUMNS = [  # header, key or function of a result row
    ("rays", "rays"), ("unamb", "unambiguous"), ("same", "same"), ("equiv", "equiv"),
    ("t_off", "t_off"), ("hit/miss", "hit_miss"), ("other", "other"),
    ("agree%", lambda r: f"{100 * r['same'] / max(1, r['rays']):.2f}"),
    ("agree%unamb", lambda r: f"{100 * r['same_on_unambiguous'] / r['unambiguous']:.2f}"
     if r["unambiguous"] else "-"),
    ("gMiss/eHit", "glint_miss_embree_hit"), ("eMiss/gHit", "embree_miss_glint_hit"),
    ("must-hit", "must_hit"),
    ("missed g/e", lambda r: f"{r['must_hit_missed_glint']}/{r['must_hit_missed_embree']}"),
    ("wrong g/e", lambda r: f"{r['unambiguous_wrong_glint']}/{r['unambiguous_wrong_embree']}"),
    ("t-known", "t_known"),
    ("t wrong g/e", lambda r: f"{r['t_known_wrong_glint']}/{r['t_known_wrong_embree']}"),
]


def table(rows, first):
    cells = [[first[0]] + [h for h, _ in COLUMNS]]
    for label, r in rows:
        cells.append([label] + [str(f(r) if callable(f) else r[f]) for _, f in COLUMNS])
    w = [max(len(c[i]) for c in cells) for i in range(len(cells[0]))]
    lines = ["| " + " | ".join(c.ljust(w[i]) if i == 0 else c.rjust(w[i]) for i, c in enumerate(row))
             + " |" for row in cells]
    lines.insert(1, "|" + "|".join("-" * (x + 2) for x in w) + "|")
    return "\n".join(lines)


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", help="folder for meshes, rays and hits (default: a new temp folder)")
    ap.add_argument("--glint", default=os.path.join(ROOT, "target", "release", "glint"))
    ap.add_argument("--families", nargs="+", default=FAMILIES, choices=FAMILIES)
    ap.add_argument("--rays", type=int, default=4096, help="rays per family (default 4096)")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--err-ulps", type=float, default=16.0,
                    help="margin for 'unambiguous' and 'must hit', in f32 ulps of the ray's "
                         "largest coordinate (default 16)")
    ap.add_argument("--json-out", help="write all results, per family and per kind, here")
    ap.add_argument("--show", type=int, default=5,
                    help="list up to N rays per family where glint is wrong (default 5)")
    a = ap.parse_args()
    if not os.access(a.glint, os.X_OK):
        raise SystemExit(f"{a.glint}: not an executable (build glint: cargo build --release)")
    out_dir = a.out or tempfile.mkdtemp(prefix="glint_hostile_")
    os.makedirs(out_dir, exist_ok=True)
    # the binary may be rebuilt while this runs (cargo in another shell): say which one ran
    glint_id = (sha256(a.glint), time.strftime("%Y-%m-%d %H:%M:%S",
                                                time.gmtime(os.path.getmtime(a.glint))))

    results = [run_family(name, a, out_dir) for name in a.families]
    if sha256(a.glint) != glint_id[0]:
        print(f"warning: {a.glint} changed during the run; families may have used different "
              "builds", file=sys.stderr)

    print(f"glint bench-rays vs Embree 4.4.0 robust (embreex), files in {out_dir}\n")
    print(table([(f"{r['family']} ({'closed' if r['closed'] else 'open'}, {r['triangles']} tris)", r)
                 for r in results], ["family"]))
    print()
    print(table([(f"{r['family']}: {k}", kr) for r in results for k, kr in r["per_kind"].items()],
                ["kind"]))
    print("""
same: same prim, t within 1e-4 relative (or both miss); equiv: other prim at that t; t_off / hit/miss /
other: the anchor's check_hits.py outcomes; agree%: same / rays (agree%unamb: on unambiguous rays);
gMiss/eHit: glint missed where Embree hit (eMiss/gHit the reverse); must-hit: rays through a closed
part's interior or a watertight sheet, by the error margin; missed g/e: of those, missed by glint /
Embree; wrong g/e: unambiguous rays whose answer differs from float64 (prim, hit/miss, or t > 1e-4);
t-known: rays whose possible nearest triangles all lie at one t (hit or prim may be ambiguous);
t wrong g/e: of those, hits reported with a t more than 1e-4 off.""")
    for r in results:
        if r["f64_contradictions"]:
            print(f"{r['family']}: {r['f64_contradictions']} must-hit rays miss in float64 (labels suspect)")
        for e in r["examples"]:
            print(f"{r['family']} ray {e['ray']} ({e['kind']}): f64 {e['f64']}, embree {e['embree']}, "
                  f"glint {e['glint']}, must_hit={e['must_hit']} unambiguous={e['unambiguous']} "
                  f"t_known={e['t_known']}")

    if a.json_out:
        from importlib.metadata import version
        try:
            head = subprocess.run(["git", "-C", ROOT, "rev-parse", "HEAD"], capture_output=True,
                                  text=True).stdout.strip()
        except OSError:
            head = None
        env = {"python": platform.python_version(), "numpy": np.__version__,
               "embreex": version("embreex"), "embree": "4.4.0 (bundled in the embreex wheel)",
               "glint": a.glint, "glint_sha256": glint_id[0], "glint_mtime_utc": glint_id[1],
               "git_head": head, "started_args": vars(a), "out_dir": out_dir}
        common.write_json(a.json_out, {"environment": env, "results": results})
        print(f"wrote {a.json_out}", file=sys.stderr)


if __name__ == "__main__":
    main()
