#!/usr/bin/env python3
"""Two glint builds side by side on the same scenes, in alternating rounds, one sitting.

    benchmarks/compare_builds.py --before /tmp/old-target/release/glint --after target/release/glint \
        --scene ../shared/scenes/cbox.xml --spp 256 --rounds 3

Or one build two ways: the same binary for both, `--before-args=--no-wavefront`; `--args` go to
both (`--args="--integrator path"`).

Prints each render's wall time (load, render and write, 2 threads) and the median ratio
after/before per scene, and whether the two images are byte-identical (the same seed).
"""
import argparse
import filecmp
import statistics
import subprocess
import tempfile
import time
from pathlib import Path


def render(binary: str, extra: list[str], scene: str, spp: int, out: Path) -> float:
    start = time.perf_counter()
    subprocess.run(
        [binary, "render", scene, "--spp", str(spp), "--seed", "1", "--threads", "2", "-o", str(out), *extra],
        check=True,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    return time.perf_counter() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--before", required=True)
    parser.add_argument("--after", required=True)
    parser.add_argument("--scene", action="append", required=True)
    parser.add_argument("--spp", type=int, default=256)
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--args", default="", help="extra render arguments for both builds")
    parser.add_argument("--before-args", default="", help="extra render arguments for the first")
    parser.add_argument("--after-args", default="", help="extra render arguments for the second")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        for scene in args.scene:
            times = {"before": [], "after": []}
            images = {k: Path(tmp) / f"{k}.pfm" for k in times}
            for _ in range(args.rounds):
                for which, binary, own in (("before", args.before, args.before_args), ("after", args.after, args.after_args)):
                    extra = args.args.split() + own.split()
                    times[which].append(render(binary, extra, scene, args.spp, images[which]))
            same = filecmp.cmp(images["before"], images["after"], shallow=False)
            b, a = statistics.median(times["before"]), statistics.median(times["after"])
            print(f"{scene}: before {b:.3f} s, after {a:.3f} s, after/before {a / b:.3f}, images identical: {same}")


if __name__ == "__main__":
    main()
