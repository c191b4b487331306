#!/usr/bin/env python3
"""glint's BVH against Embree 4 on the same meshes and ray sets, in one sitting.

Runs ../shared/anchors/embree/bench_embree.py (Embree through embreex) and then
`glint bench-rays` on every mesh and ray set, and prints one Markdown table of rates and
ratios (glint / Embree). Standard library only; Embree runs in its own venv.

    python3 benchmarks/compare_embree.py --embree-python ~/venvs/embree/bin/python \
        --rays-dir /tmp/rt_anchor_rays [--meshes bunny dragon] [--threads 1] [--repeats 3] [--rounds 5]

This machine's speed drifts by 20 % or more from minute to minute (a shared host), so one
Embree run followed by one glint run can be skewed either way. With --rounds N the pair runs
N times back to back; the table gives each side's median rate and the median of the N
per-round ratios.

The ray sets come from the anchor: `$EMBREE_PY ../shared/anchors/embree/gen_rays.py --rays-dir DIR`.
Build glint first: `cargo build --release`.
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SHARED = os.path.join(ROOT, "..", "shared")
MESHES = {"bunny": "stanford_bunny.ply.gz", "dragon": "stanford_dragon.ply.gz"}
SETS = ["primary", "diffuse", "random"]
# glint's queries (the name in the table, bench-rays' field) and the Embree query each is set
# against: one ray at a time, then the same closest hits with eight rays' traversals
# interleaved (Geometry::closest_primitives), against Embree's one-ray closest hit, which is
# what embreex runs (a loop of rtcIntersect1).
QUERIES = [("closest", "closest_mrays", "closest"),
           ("closest, interleaved", "interleaved_mrays", "closest"),
           ("occluded", "anyhit_mrays", "occluded")]


def run_embree(args):
    out = os.path.join(tempfile.mkdtemp(), "embree.json")
    cmd = [args.embree_python, os.path.join(SHARED, "anchors", "embree", "bench_embree.py"),
           "--rays-dir", args.rays_dir, "--meshes", *args.meshes, "--threads", str(args.threads),
           "--robust", "on", "--repeats", str(args.repeats), "--json-out", out]
    print("$", " ".join(cmd), file=sys.stderr)
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
    with open(out) as f:
        results = json.load(f)["results"]
    embree = {}
    for r in results:
        if r["kind"] == "build":
            embree[(r["mesh"], "build")] = r["commit_s_best"]
        elif r["kind"] == "trace":
            embree[(r["mesh"], r["set"], r["query"])] = r["mrays_best"]
    return embree


def run_glint(args, mesh, ray_set):
    rays = os.path.join(args.rays_dir, mesh, ray_set)
    cmd = [args.glint, "bench-rays", os.path.join(SHARED, "meshes", MESHES[mesh]), rays + ".rays",
           "--hits", rays + ".hits", "--threads", str(args.threads), "--repeat", str(args.repeats)]
    print("$", " ".join(cmd), file=sys.stderr)
    last = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout.strip().splitlines()[-1]
    return dict(kv.split("=", 1) for kv in last.split())


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--embree-python", required=True)
    p.add_argument("--rays-dir", required=True)
    p.add_argument("--meshes", nargs="+", default=["bunny", "dragon"], choices=sorted(MESHES))
    p.add_argument("--threads", type=int, default=1)
    p.add_argument("--repeats", type=int, default=3)
    p.add_argument("--rounds", type=int, default=1, help="Embree-then-glint pairs; medians are reported")
    p.add_argument("--glint", default=os.path.join(ROOT, "target", "release", "glint"))
    args = p.parse_args()

    print("load average before:", os.getloadavg()[0], file=sys.stderr)
    rounds = []  # per round: {(mesh, set, query) or (mesh, "build"): (glint, embree)}
    for r in range(args.rounds):
        print(f"round {r + 1} of {args.rounds}", file=sys.stderr)
        embree = run_embree(args)
        pairs = {}
        for mesh in args.meshes:
            for ray_set in SETS:
                g = run_glint(args, mesh, ray_set)
                for query, key, embree_query in QUERIES:
                    pairs[(mesh, ray_set, query)] = (float(g[key]), embree[(mesh, ray_set, embree_query)])
                if ray_set == SETS[0]:
                    pairs[(mesh, "build")] = (float(g["build_s"]), embree[(mesh, "build")])
                print(f"{mesh}/{ray_set}: matches {g['matches']}", file=sys.stderr)
        rounds.append(pairs)

    def median(key):
        ours = statistics.median(p[key][0] for p in rounds)
        theirs = statistics.median(p[key][1] for p in rounds)
        ratio = statistics.median(p[key][0] / p[key][1] for p in rounds)
        return ours, theirs, ratio

    print("| mesh | rays | query | glint Mrays/s | Embree Mrays/s | glint / Embree |")
    print("| --- | --- | --- | ---: | ---: | ---: |")
    for mesh in args.meshes:
        for ray_set in SETS:
            for query, _, _ in QUERIES:
                ours, theirs, ratio = median((mesh, ray_set, query))
                print(f"| {mesh} | {ray_set} | {query} | {ours:.2f} | {theirs:.2f} | {ratio:.2f} |")
    print()
    print("| mesh | glint build s | Embree build s | glint / Embree |")
    print("| --- | ---: | ---: | ---: |")
    for mesh in args.meshes:
        ours, theirs, ratio = median((mesh, "build"))
        print(f"| {mesh} | {ours:.3f} | {theirs:.3f} | {ratio:.2f} |")
    print("load average after:", os.getloadavg()[0], file=sys.stderr)


if __name__ == "__main__":
    main()
