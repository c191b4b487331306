#!/usr/bin/env python3
"""glint against Mitsuba 3 on scenes of Mitsuba's own regression suite (issues 25 and 48): the
error each reaches in equal time, as a ratio, in one sitting.

By default three long renders (a glossy sphere, instances, a hall of mirrors); with `--all`,
every one of the suite's 41 scenes with an RGB reference, at the samples per pixel Mitsuba's
own test renders them (2,000,000 / pixels, times `--spp-scale`), followed by the geometric
mean of the ratios and the worst scene. `--only SUBSTRING` keeps the scenes whose path
contains it.

For each scene both renderers render the same number of samples per pixel, each timed on its
render alone (Mitsuba: the second `mi.render` of a loaded scene, so its kernels are compiled
or cached; glint: the render time its summary line prints). Each image is scored against the
suite's reference with relMSE = mean((a − b)² / (b² + 10⁻²)) over pixels and channels (the
anchors' measure). For unbiased renderers relMSE falls as 1/time, so relMSE × seconds is the
error at equal time; the table gives glint's product over Mitsuba's (below 1: glint is closer
to the reference after the same time). Each figure is the median of `--rounds` renders with
different seeds; the scenes' `moment` wrapper stays in both (Mitsuba pays for two extra film
channels, glint renders the nested integrator).

    python3 benchmarks/mitsuba_suite_equal_time.py --mitsuba-python ~/venvs/mitsuba/bin/python \
        [--glint target/release/glint] [--variant llvm_ad_rgb] [--rounds 3] [--threads 2] \
        [--all [--spp-scale 1.0]] [--only projector]

Needs numpy in the Python that runs it and Mitsuba 3 in `--mitsuba-python`'s (the anchors'
`mitsuba/setup.sh` makes that venv). Build glint first: `cargo build --release`.
"""
import argparse
import json
import math
import os
import re
import statistics
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
# mitsuba-data's layout: each scene's `<path value="../../../common"/>` resolves in place.
SUITE = os.path.normpath(os.path.join(ROOT, "..", "shared", "mitsuba-data", "tests"))

# (group, scene file, samples per pixel): a glossy sphere under three kinds of light, shape
# groups placed three times, and a hall of mirrors (long specular paths).
SCENES = [
    ("bsdf_spheres", "test_roughplastic_linear_path.xml", 4096),
    ("instancing", "test_instancing_path.xml", 2048),
    ("infinite_mirrors", "scene_path.xml", 1024),
]

MITSUBA_RENDER = r"""
import json, sys, time
import numpy as np
import mitsuba as mi
import drjit as dr
variant, path, integrator, spp, seed, threads, out = sys.argv[1:8]
mi.set_variant(variant)
mi.set_log_level(mi.LogLevel.Error)
dr.set_thread_count(int(threads))
scene = mi.load_file(path, integrator=integrator, spp=int(spp))
mi.render(scene, spp=int(spp), seed=int(seed) + 1000)  # compiles or loads the kernels
dr.sync_thread()
start = time.perf_counter()
image = mi.render(scene, spp=int(spp), seed=int(seed))
dr.eval(image)
dr.sync_thread()
seconds = time.perf_counter() - start
rgb = np.array(image)[..., :3].astype(np.float32)
mi.Bitmap(rgb.copy(), mi.Bitmap.PixelFormat.RGB).write(out)
print(json.dumps({"seconds": seconds}))
"""


# Mitsuba's test: 2,000,000 samples per image, whatever its size.
SAMPLES_PER_IMAGE = 2_000_000


def suite_scenes():
    """Every suite scene with an RGB reference, as (group, file name), sorted."""
    found = []
    scenes = os.path.join(SUITE, "scenes")
    for group in sorted(os.listdir(scenes)):
        for name in sorted(os.listdir(os.path.join(scenes, group))):
            if name.endswith(".xml") and os.path.exists(reference_path(group, name)):
                found.append((group, name))
    return found


def reference_path(group, name):
    stem = name[:-4]
    base = stem[:stem.rfind("_")]
    return os.path.join(SUITE, "scenes", group, "refs", f"{base}_ref_rgb.exr")


def read_exr(python, path):
    """RGB of an EXR as nested lists, read by Mitsuba's Python (numpy there)."""
    code = ("import sys, json, numpy as np, mitsuba as mi; mi.set_variant('scalar_rgb');"
            "a = np.array(mi.Bitmap(sys.argv[1]))[..., :3]; print(json.dumps(a.tolist()))")
    return json.loads(subprocess.run([python, "-c", code, path], capture_output=True, text=True,
                                     check=True).stdout)


def relmse(image, reference):
    import numpy as np
    a, b = np.asarray(image, dtype=np.float64), np.asarray(reference, dtype=np.float64)
    return float(np.mean((a - b) ** 2 / (b * b + 1e-2)))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--mitsuba-python", required=True)
    parser.add_argument("--glint", default=os.path.join(ROOT, "target", "release", "glint"))
    parser.add_argument("--variant", default="llvm_ad_rgb")
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--all", action="store_true", help="every suite scene, at Mitsuba's test spp")
    parser.add_argument("--spp-scale", type=float, default=1.0, help="with --all: the test's spp times this")
    parser.add_argument("--only", help="keep the scenes whose group/file contains this")
    args = parser.parse_args()

    if not os.path.isdir(SUITE):
        parser.error(f"Mitsuba's suite not found at {SUITE}")
    if args.all:
        scenes = [(group, name, None) for group, name in suite_scenes()]
    else:
        scenes = SCENES
    if args.only:
        scenes = [s for s in scenes if args.only in f"{s[0]}/{s[1]}"]

    rows = []
    with tempfile.TemporaryDirectory() as scratch:
        for group, name, spp in scenes:
            path = os.path.join(SUITE, "scenes", group, name)
            stem = name[:-4]
            integrator = stem[stem.rfind("_") + 1:]
            reference = read_exr(args.mitsuba_python, reference_path(group, name))
            if spp is None:
                pixels = len(reference) * len(reference[0])
                spp = max(1, round(SAMPLES_PER_IMAGE // pixels * args.spp_scale))
            results = {"mitsuba": [], "glint": []}
            for seed in range(args.rounds):
                out = os.path.join(scratch, f"{stem}-mitsuba-{seed}.exr")
                run = subprocess.run([args.mitsuba_python, "-c", MITSUBA_RENDER, args.variant, path,
                                      integrator, str(spp), str(seed), str(args.threads), out],
                                     capture_output=True, text=True, check=True)
                seconds = json.loads(run.stdout.strip().splitlines()[-1])["seconds"]
                results["mitsuba"].append((seconds, relmse(read_exr(args.mitsuba_python, out), reference)))

                out = os.path.join(scratch, f"{stem}-glint-{seed}.exr")
                run = subprocess.run([args.glint, "render", path, "-D", f"spp={spp}", "-D",
                                      f"integrator={integrator}", "--seed", str(seed), "--threads",
                                      str(args.threads), "-o", out], capture_output=True, text=True,
                                     check=True)
                seconds = float(re.search(r" in ([0-9.]+) s", run.stderr + run.stdout).group(1))
                results["glint"].append((seconds, relmse(read_exr(args.mitsuba_python, out), reference)))
            summary = {}
            for who, runs in results.items():
                summary[who] = (statistics.median(s for s, _ in runs), statistics.median(e for _, e in runs),
                                statistics.median(s * e for s, e in runs))
            rows.append((f"{group}/{stem}", spp, summary))
            (mt, me, mp), (gt, ge, gp) = summary["mitsuba"], summary["glint"]
            print(f"{group}/{stem}: {spp} spp, Mitsuba {mt:.3f} s, glint {gt:.3f} s, "
                  f"equal-time error {gp / mp:.2f}×", file=sys.stderr, flush=True)

    print(f"| scene | spp | Mitsuba {args.variant} s | glint s | Mitsuba relMSE | glint relMSE "
          "| speed (Mitsuba s / glint s) | equal-time error (glint / Mitsuba) |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- |")
    for scene, spp, s in rows:
        (mt, me, mp), (gt, ge, gp) = s["mitsuba"], s["glint"]
        print(f"| {scene} | {spp} | {mt:.3f} | {gt:.3f} | {me:.3g} | {ge:.3g} | {mt / gt:.2f}× "
              f"| {gp / mp:.2f}× |")
    ratios = [(s["glint"][2] / s["mitsuba"][2], scene) for scene, _, s in rows]
    speeds = [s["mitsuba"][0] / s["glint"][0] for _, _, s in rows]
    if ratios:
        geomean = math.exp(sum(math.log(r) for r, _ in ratios) / len(ratios))
        worst, worst_scene = max(ratios)
        behind = sum(1 for r, _ in ratios if r > 1.0)
        speed = math.exp(sum(math.log(r) for r in speeds) / len(speeds))
        print(f"\n{len(ratios)} scenes: equal-time error (glint / Mitsuba) geometric mean {geomean:.2f}×, "
              f"worst {worst:.2f}× ({worst_scene}), glint behind on {behind}; speed geometric mean {speed:.2f}×")


if __name__ == "__main__":
    main()
