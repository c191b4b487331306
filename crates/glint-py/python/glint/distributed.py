"""Rendering across machines on Ray: the samples of every pixel split into ranges, each range
rendered by a Ray task (``Scene.render(samples=(a, b))``), the parts merged by the driver into
the image one render gives, bit for bit.

    import glint.distributed
    image = glint.distributed.render("scenes/cornell-box.toml", spp=256, tasks=8).image

From the command line (a local Ray, or a cluster's address):

    python -m glint.distributed scenes/cornell-box.toml --spp 256 --tasks 8 -o cornell.exr

The output's extension names its format, as for ``glint merge``: an EXR keeps the exact sums
(a partial render, to merge further); PNG, PFM and HDR hold the image alone.
"""

import argparse
import os
import sys


def ranges(spp, tasks):
    """spp samples split into `tasks` contiguous ranges as even as can be (none empty)."""
    if spp < 1 or tasks < 1:
        raise ValueError(f"spp and tasks must be at least 1, got spp={spp}, tasks={tasks}")
    tasks = min(tasks, spp)
    bounds = [spp * k // tasks for k in range(tasks + 1)]
    return [(bounds[k], bounds[k + 1]) for k in range(tasks)]


def _render_part(scene_path, params, samples, seed, integrator, threads):
    import glint

    scene = glint.load_file(scene_path, **params)
    return scene.render(samples=samples, seed=seed, integrator=integrator, threads=threads)


def render(scene_path, spp, tasks=4, seed=None, integrator=None, threads_per_task=1, address=None, **params):
    """Renders `spp` samples per pixel of the scene file in `tasks` Ray tasks and merges them.

    Uses the running Ray (``ray.init`` already called), else starts one (``address`` to join
    a cluster). Each task needs the scene's files at the same path. Returns the merged
    ``glint.Partial`` (its ``.image`` the image; ``.save(path)`` writes it).
    """
    import ray

    import glint

    if not ray.is_initialized():
        ray.init(address=address)
    scene_path = os.path.abspath(scene_path)
    part = ray.remote(num_cpus=threads_per_task)(_render_part)
    futures = [part.remote(scene_path, params, r, seed, integrator, threads_per_task) for r in ranges(spp, tasks)]
    return glint.merge(ray.get(futures))


def main(argv=None):
    parser = argparse.ArgumentParser(prog="python -m glint.distributed", description=__doc__.split("\n\n")[0])
    parser.add_argument("scene")
    parser.add_argument("--spp", type=int, required=True)
    parser.add_argument("--tasks", type=int, default=4)
    parser.add_argument("--seed", type=int)
    parser.add_argument("--integrator")
    parser.add_argument("--threads-per-task", type=int, default=1)
    parser.add_argument("--address", help="a Ray cluster's address (default: start a local Ray)")
    parser.add_argument(
        "-o",
        "--output",
        required=True,
        help="the merged image: .exr a partial EXR (exact sums, to merge further); .png, .pfm, .hdr the image alone",
    )
    args = parser.parse_args(argv)
    # An output that cannot be written is refused before any rendering.
    from glint._glint import _check_output

    _check_output(args.output)
    merged = render(
        args.scene,
        args.spp,
        tasks=args.tasks,
        seed=args.seed,
        integrator=args.integrator,
        threads_per_task=args.threads_per_task,
        address=args.address,
    )
    merged.save(args.output)
    print(f"merged {args.tasks} tasks: samples {merged.samples} -> {args.output}", file=sys.stderr)


if __name__ == "__main__":
    main()
