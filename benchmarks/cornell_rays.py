#!/usr/bin/env python3
"""glint's ray queries against Embree 4 on the Cornell box's own rays, in one sitting.

The path tracer's speed target is set on the Cornell box (32 triangles), where the anchor's
meshes (bunny, dragon) say little about the queries' cost. This writes the box as a PLY and
three ray sets in the Embree anchor's format (../shared/anchors/embree/README.md), then times
Embree (through embreex, robust mode, one ray at a time) and `glint bench-rays` on them,
alternating, and prints one Markdown table of rates and ratios (glint / Embree):

* `primary`: one ray per pixel sample from the scene's camera (256 x 256, 4 samples per
  pixel, jittered), as the render's camera rays;
* `diffuse`: from each primary hit, cosine-weighted about the normal turned toward the
  camera, the origin offset by 1e-5 of the box's diagonal: the second bounce;
* `shadow`: from the same points (those below the light, which emits downward) to a uniform
  point on the light, ending 1e-4 of the way short of it, as glint's shadow rays
  (`SHADOW_EPSILON`); timed as any-hit queries.

Run it with the Python of the Embree anchor's venv (numpy and embreex):

    ~/venvs/embree/bin/python benchmarks/cornell_rays.py [--rounds 3] [--repeats 5] [--glint BINARY] \
        [--embree-packets /tmp/embree_packets]

`--embree-packets` adds Embree's packets of 16 rays (what Mitsuba 3 calls on AVX-512 hosts),
timed by benchmarks/embree_packets.c (its header says how to build it), in a robust scene as
the anchor builds it and in one built as Mitsuba 3 builds its scenes (not robust).

Build glint first: `cargo build --release`. Both sides run on one thread.
"""
import argparse
import json
import math
import os
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SHARED = os.path.join(ROOT, "..", "shared")
sys.path.insert(0, os.path.join(SHARED, "anchors", "embree"))
import common  # noqa: E402  (the anchor's PLY, ray and hit file helpers)

SETS = {"primary": "closest", "diffuse": "closest", "shadow": "occluded"}


def box_mesh():
    scene = common.read_json(os.path.join(SHARED, "scenes", "cbox.json"))
    vertices, faces = [], []
    for quad in scene["quads"]:
        first = len(vertices)
        vertices += quad["v"]
        # The scene's own split: (v0, v1, v2) and (v0, v2, v3).
        faces += [[first, first + 1, first + 2], [first, first + 2, first + 3]]
    light = next(q["v"] for q in scene["quads"] if q["name"] == "light")
    return np.array(vertices, np.float32), np.array(faces, np.int32), np.array(light, np.float64), scene["camera"]


def ray_records(origins, directions, t_max):
    rays = np.zeros((len(origins), 8), np.float32)
    rays[:, 0:3], rays[:, 3:6], rays[:, 7] = origins, directions, t_max
    return rays


def make_sets(vertices, faces, light, camera, scene, rng, res=256, spp=4):
    # Camera rays: a pinhole at `origin` looking along +z (the scene's camera), image x to -x.
    n = res * res * spp
    pixel = np.repeat(np.arange(res * res), spp)
    x = (pixel % res + rng.random(n)) / res
    y = (pixel // res + rng.random(n)) / res
    tan = math.tan(math.radians(camera["fov_y_deg"]) / 2)
    d = np.stack([-(2 * x - 1) * tan, (1 - 2 * y) * tan, np.ones(n)], 1)
    d /= np.linalg.norm(d, axis=1)[:, None]
    o = np.tile(np.array(camera["origin"], np.float64), (n, 1))
    primary = ray_records(o, d, np.inf)

    t, prim = common.trace_closest(scene, primary)
    hit = prim != 0xFFFFFFFF
    a, b, c = (vertices[faces[prim[hit], k]].astype(np.float64) for k in range(3))
    normal = np.cross(b - a, c - a)
    normal /= np.linalg.norm(normal, axis=1)[:, None]
    normal = np.where((np.sum(normal * d[hit], 1) > 0)[:, None], -normal, normal)
    diagonal = np.linalg.norm(vertices.max(0) - vertices.min(0))
    points = o[hit] + d[hit] * t[hit][:, None] + 1e-5 * diagonal * normal

    # Cosine-weighted directions about the normal (Duff et al.'s orthonormal basis).
    u1, u2 = rng.random(len(points)), rng.random(len(points))
    r, phi = np.sqrt(u1), 2 * np.pi * u2
    local = np.stack([r * np.cos(phi), r * np.sin(phi), np.sqrt(1 - u1)], 1)
    sign = np.where(normal[:, 2] >= 0, 1.0, -1.0)
    k = -1 / (sign + normal[:, 2])
    m = normal[:, 0] * normal[:, 1] * k
    tangent = np.stack([1 + sign * normal[:, 0] ** 2 * k, sign * m, -sign * normal[:, 0]], 1)
    bitangent = np.stack([m, sign + normal[:, 1] ** 2 * k, -normal[:, 1]], 1)
    bounce = tangent * local[:, :1] + bitangent * local[:, 1:2] + normal * local[:, 2:]
    diffuse = ray_records(points, bounce, np.inf)

    s, t2 = rng.random(len(points)), rng.random(len(points))
    target = light[0] + (light[1] - light[0]) * s[:, None] + (light[3] - light[0]) * t2[:, None]
    # The light emits downward only: glint traces no shadow ray from points above its plane
    # (the ceiling's), so neither does this set.
    below = points[:, 1] < light[:, 1].min()
    to_light = (target - points)[below]
    distance = np.linalg.norm(to_light, axis=1)
    shadow = ray_records(points[below], to_light / distance[:, None], distance * (1 - 1e-4))
    return {"primary": primary, "diffuse": diffuse, "shadow": shadow}


def embree_rate(scene, rays, query, repeats):
    o, d = np.ascontiguousarray(rays[:, 0:3]), np.ascontiguousarray(rays[:, 3:6])
    t_max = np.ascontiguousarray(rays[:, 7])
    best = math.inf
    for _ in range(repeats):
        start = time.perf_counter()
        scene.run(o, d, dists=t_max.copy(), query="INTERSECT" if query == "closest" else "OCCLUDED")
        best = min(best, time.perf_counter() - start)
    return len(rays) / best / 1e6


def glint_rates(glint, mesh, rays_path, repeats):
    out = subprocess.run([glint, "bench-rays", mesh, rays_path, "--hits", rays_path.replace(".rays", ".hits"),
                          "--threads", "1", "--repeat", str(repeats)], check=True, capture_output=True, text=True)
    last = dict(kv.split("=", 1) for kv in out.stdout.strip().splitlines()[-1].split())
    return {"closest": float(last["closest_mrays"]), "occluded": float(last["anyhit_mrays"]), "matches": last["matches"]}


def embree_packet_rate(binary, mesh, rays_path, query, repeats, as_mitsuba=False):
    cmd = [binary, mesh, rays_path, query, str(repeats)] + (["mitsuba"] if as_mitsuba else [])
    fields = dict(kv.split("=", 1) for kv in subprocess.run(cmd, check=True, capture_output=True, text=True).stdout.split())
    return float(fields["packet16_mrays"])


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--glint", default=os.path.join(ROOT, "target", "release", "glint"))
    p.add_argument("--rounds", type=int, default=3, help="Embree-then-glint pairs; medians are reported")
    p.add_argument("--repeats", type=int, default=5, help="timed passes over each set; the best counts")
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--dir", help="where the mesh and ray sets go (default: a new temporary folder)")
    p.add_argument("--embree-packets", help="the built benchmarks/embree_packets.c, for Embree's packets of 16")
    args = p.parse_args()

    os.sched_setaffinity(0, {min(os.sched_getaffinity(0))})  # one thread, both sides
    directory = args.dir or tempfile.mkdtemp(prefix="cornell_rays_")
    os.makedirs(directory, exist_ok=True)
    vertices, faces, light, camera = box_mesh()
    mesh = os.path.join(directory, "cbox.ply")
    common.write_ply(mesh, vertices, faces, comments=["the Cornell box of ../shared/scenes/cbox.json"])
    scene = common.build_scene(vertices, faces, robust=True)[0]
    sets = make_sets(vertices, faces, light, camera, scene, np.random.default_rng(args.seed))
    for name, rays in sets.items():
        path = os.path.join(directory, name + ".rays")
        common.save_rays(path, rays)
        common.save_hits(path.replace(".rays", ".hits"), *common.trace_closest(scene, rays))
    print(f"mesh and ray sets in {directory}; load average before: {os.getloadavg()[0]:.2f}", file=sys.stderr)

    # Per set: glint's, Embree's and (with --embree-packets) Embree's packets' rates, robust and
    # as Mitsuba builds the scene, one per round.
    rates = {name: ([], [], [], []) for name in sets}
    matches = {}
    for r in range(args.rounds):
        for name, rays in sets.items():
            query, path = SETS[name], os.path.join(directory, name + ".rays")
            rates[name][1].append(embree_rate(scene, rays, query, args.repeats))
            if args.embree_packets:
                for column, as_mitsuba in ((2, False), (3, True)):
                    rates[name][column].append(
                        embree_packet_rate(args.embree_packets, mesh, path, query, args.repeats, as_mitsuba))
            glint = glint_rates(args.glint, mesh, path, args.repeats)
            rates[name][0].append(glint[query])
            matches[name] = glint["matches"]
        print(f"round {r + 1} of {args.rounds} done", file=sys.stderr)

    packets = bool(args.embree_packets)
    print("| ray set | rays | query | glint Mrays/s | Embree Mrays/s | glint / Embree"
          + (" | Embree, packets of 16 | glint / packets | packets, as Mitsuba builds | glint / those"
             if packets else "") + " | glint's hits = Embree's |")
    print("| --- | ---: | --- | ---: | ---: | ---: |" + (" ---: | ---: | ---: | ---: |" if packets else "") + " ---: |")
    for name, rays in sets.items():
        glint, embree, sixteen, mitsuba = rates[name]
        # Ratios per round (the pair ran back to back), then their median.
        ratio = statistics.median(g / e for g, e in zip(glint, embree))
        row = (f"| {name} | {len(rays):,} | {SETS[name]} hit | {statistics.median(glint):.2f} | "
               f"{statistics.median(embree):.2f} | {ratio:.2f}")
        if packets:
            for peer in (sixteen, mitsuba):
                row += (f" | {statistics.median(peer):.2f} | "
                        f"{statistics.median(g / p for g, p in zip(glint, peer)):.2f}")
        print(row + f" | {matches[name]} |")
    print(json.dumps({"dir": directory, "rounds": args.rounds, "repeats": args.repeats}), file=sys.stderr)


if __name__ == "__main__":
    main()
