#!/usr/bin/env python3
"""glint against Mitsuba 3 on scenes of Mitsuba's own regression suite (issue 25): the error
each reaches in equal time, as a ratio, in one sitting.

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
        [--glint target/release/glint] [--variant llvm_ad_rgb] [--rounds 3] [--threads 2]

Needs numpy in the Python that runs it and Mitsuba 3 in `--mitsuba-python`'s (the anchors'
`mitsuba/setup.sh` makes that venv). Build glint first: `cargo build --release`.
"""
import argparse
import json
import os
import re
import statistics
import subprocess
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
    args = parser.parse_args()

    rows = []
    with tempfile.TemporaryDirectory() as scratch:
        for group, name, spp in SCENES:
            path = os.path.join(SUITE, "scenes", group, name)
            stem = name[:-4]
            integrator = stem[stem.rfind("_") + 1:]
            base = stem[:stem.rfind("_")]
            reference = read_exr(args.mitsuba_python,
                                 os.path.join(SUITE, "scenes", group, "refs", f"{base}_ref_rgb.exr"))
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

    print(f"| scene | spp | Mitsuba {args.variant} s | glint s | Mitsuba relMSE | glint relMSE "
          "| speed (Mitsuba s / glint s) | equal-time error (glint / Mitsuba) |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- |")
    for scene, spp, s in rows:
        (mt, me, mp), (gt, ge, gp) = s["mitsuba"], s["glint"]
        print(f"| {scene} | {spp} | {mt:.3f} | {gt:.3f} | {me:.3g} | {ge:.3g} | {mt / gt:.2f}× "
              f"| {gp / mp:.2f}× |")


if __name__ == "__main__":
    main()
