#!/usr/bin/env python3
"""The Python module and Ray against the command line, on the Cornell box, one sitting.

    target/python-venv/bin/python benchmarks/python_ray.py --glint target/release/glint --spp 64 --rounds 3

(`cargo test -p glint-py --release` makes that virtual environment, with the module, numpy and
Ray in it.) Times, best of the rounds, 2 threads in all:
- the CLI: `glint render` of the scene (load, render, write an EXR);
- Python: `glint.load_file(...).render(spp=...)` (load, render, the numpy array);
- Ray on a local cluster of 2 CPUs: `glint.distributed.render(..., tasks=N)` for 1 and 4
  tasks of one thread each (every task loads the scene; the driver merges), the cluster
  started before the clock.
Prints each time and the ratios: Python / CLI, Ray (4 tasks) / CLI, and the speed-up of 4
tasks over 1 (ideally 2 on 2 cores).
"""
import argparse
import os
import subprocess
import tempfile
import time

import glint
import glint.distributed
import ray


def best(rounds, run):
    times = []
    for _ in range(rounds):
        start = time.perf_counter()
        run()
        times.append(time.perf_counter() - start)
    return min(times)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--glint", default="target/release/glint")
    parser.add_argument("--scene", default="scenes/cornell-box.toml")
    parser.add_argument("--spp", type=int, default=64)
    parser.add_argument("--rounds", type=int, default=3)
    args = parser.parse_args()
    scene = os.path.abspath(args.scene)
    out = os.path.join(tempfile.mkdtemp(), "cli.exr")
    cli = best(args.rounds, lambda: subprocess.run(
        [args.glint, "render", scene, "--spp", str(args.spp), "--threads", "2", "-q", "-o", out], check=True))
    python = best(args.rounds, lambda: glint.load_file(scene).render(spp=args.spp, threads=2))
    ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False)
    # One warm-up, so that the workers exist before the clock.
    glint.distributed.render(scene, args.spp, tasks=2)
    one = best(args.rounds, lambda: glint.distributed.render(scene, args.spp, tasks=1))
    four = best(args.rounds, lambda: glint.distributed.render(scene, args.spp, tasks=4))
    ray.shutdown()
    print(f"CLI {cli:.3f} s, Python {python:.3f} s, Ray 1 task {one:.3f} s, Ray 4 tasks {four:.3f} s ({args.spp} spp)")
    print(f"Python / CLI {python / cli:.3f}; Ray 4 tasks / CLI {four / cli:.3f}; 4 tasks over 1: {one / four:.2f}x")


if __name__ == "__main__":
    main()
