#!/usr/bin/env python3
"""Mitsuba 3's documentation scenes (mitsuba-data's `docs/scenes`) through glint (issue 52):
which load, which are refused and why, and, given Mitsuba's Python, whether each image passes
Mitsuba's per-pixel Z-test against Mitsuba's own render of the same scene.

    python3 benchmarks/mitsuba_docs_scenes.py DOCS_SCENES [--mitsuba-python PY]
        [--glint target/release/glint] [--scale 8] [--spp 64] [--reference-spp 256]
        [--threads 2] [--only NAME ...] [--keep DIR] [--json]

DOCS_SCENES is mitsuba-data's `docs/scenes` folder with `../../common` beside it, as the
repository lays them out (extract both, e.g. `git archive HEAD docs/scenes common`). Every
`*.xml` directly inside it is a scene, as for Mitsuba's own `render_documentation_images.py`;
`include/` holds the parts they share.

The scenes are copied into a scratch folder (`common` linked, not copied) with each film's
width and height divided by `--scale`, the only change, so that both renderers render the
same small images; messages name the original files (the copy keeps every line in place).
glint renders each at `--spp` (and `-D spp=…`, as Mitsuba's `render_documentation_images.py`
passes `spp`: some scenes use `$spp` with no default); a refused scene is reported with
glint's message, which names the element's line.

With `--mitsuba-python` (the anchors' `mitsuba/setup.sh` makes that venv; `scalar_rgb` is
enough), Mitsuba renders each scene glint renders at `--reference-spp` inside a `moment`
integrator, which gives each pixel's per-sample variance, and `glint compare IMAGE REF
--variance VAR` runs Mitsuba's Z-test (XYZ, Šidák-corrected α = 1 %, a pass at ≥ 99.75 % of
the pixel channels; glint's sample count from its EXR header). Mitsuba's image is itself
noisy, so the variance handed to the test is its per-sample variance × (1 + glint spp /
Mitsuba spp): the variance of the difference of the two means, per glint sample. A scene
Mitsuba's `scalar_rgb` cannot render is reported as such; for a scene glint refuses, whether
Mitsuba's `scalar_rgb` loads it.

At a few hundred samples the test finds biases of a few percent, not of a few tenths of one
(the suite test, `crates/glint-cli/tests/mitsuba_suite.rs`, is the finer one), and a scene
whose noise is heavy-tailed (light reaching most pixels along rare paths) can fail it because
Mitsuba's few samples underestimate the variance: rerun such a scene with `--only NAME` and
more samples before calling it a bias.
"""
import argparse
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

MITSUBA_RENDER = r"""
import json, sys
import numpy as np
import mitsuba as mi
import drjit as dr
path, spp, seed, threads, image_out, variance_out, glint_spp = sys.argv[1:8]
mi.set_variant("scalar_rgb")
mi.set_log_level(mi.LogLevel.Error)
dr.set_thread_count(max(2, int(threads)))  # EXR I/O hangs with one thread (anchors' README)
try:
    scene = mi.load_file(path, spp=int(spp))  # as Mitsuba's render_documentation_images.py
except RuntimeError as error:  # Mitsuba 3.9 refuses a parameter the scene does not use
    if "unused parameters" not in str(error):
        raise
    scene = mi.load_file(path)
moment = mi.load_dict({"type": "moment", "nested": scene.integrator()})
mi.render(scene, integrator=moment, spp=int(spp), seed=int(seed))
spp = scene.sensors()[0].sampler().sample_count()
layers = dict(scene.sensors()[0].film().bitmap(raw=False).split())
# The image is the root layer (RGB); `moment` keeps the nested integrator's mean and second
# moment in XYZ, where Mitsuba's Z-test works. glint's test turns the variance it is given
# into XYZ by the sRGB matrix, so it is handed that matrix's inverse of the XYZ variance.
image = np.array(layers["<root>"], dtype=np.float64)[..., :3]
mean = np.array(layers["nested"], dtype=np.float64)[..., :3]
second = np.array(layers["m2_nested"], dtype=np.float64)[..., :3]
variance_xyz = np.maximum(second - mean * mean, 0.0) * (1.0 + float(glint_spp) / spp)
XYZ_FROM_RGB = np.array([[0.412453, 0.357580, 0.180423], [0.212671, 0.715160, 0.072169],
                         [0.019334, 0.119193, 0.950227]])
variance = variance_xyz @ np.linalg.inv(XYZ_FROM_RGB).T
mi.Bitmap(image.astype(np.float32), mi.Bitmap.PixelFormat.RGB).write(image_out)
mi.Bitmap(variance.astype(np.float32), mi.Bitmap.PixelFormat.RGB).write(variance_out)
print(json.dumps({"spp": spp}))
"""

MITSUBA_LOAD = r"""
import sys
import mitsuba as mi
mi.set_variant("scalar_rgb")
mi.set_log_level(mi.LogLevel.Error)
try:
    mi.load_file(sys.argv[1], spp=int(sys.argv[2]))
except RuntimeError as error:
    if "unused parameters" not in str(error):
        raise
    mi.load_file(sys.argv[1])
"""

FILM = re.compile(r"<film\b.*?</film>", re.S)
SIZE = re.compile(r'(<integer\s+name="(?:width|height)"\s+value=")(\d+)(")')


def shrink_films(text, scale):
    """The scene text with every film's literal width and height divided by `scale`."""
    def size(m):
        return f"{m.group(1)}{max(1, round(int(m.group(2)) / scale))}{m.group(3)}"
    return FILM.sub(lambda film: SIZE.sub(size, film.group(0)), text)


def scratch_copy(docs, scratch, scale):
    """docs/scenes copied under scratch/docs/scenes (XML with smaller films, the rest linked)
    and scratch/common linked to the original, so every relative path still resolves."""
    scenes = os.path.join(scratch, "docs", "scenes")
    for folder, _, files in os.walk(docs):
        target = os.path.join(scenes, os.path.relpath(folder, docs))
        os.makedirs(target, exist_ok=True)
        for name in files:
            source = os.path.join(folder, name)
            if name.endswith(".xml"):
                with open(source, encoding="utf-8", errors="surrogateescape") as f:
                    text = f.read()
                with open(os.path.join(target, name), "w", encoding="utf-8", errors="surrogateescape") as f:
                    f.write(shrink_films(text, scale))
            else:
                os.symlink(os.path.abspath(source), os.path.join(target, name))
    common = os.path.normpath(os.path.join(docs, "..", "..", "common"))
    if os.path.isdir(common):
        os.symlink(common, os.path.join(scratch, "common"))
    return scenes


def first_error(text):
    """glint's message: the `file:line:column: message` line of its error."""
    lines = [line for line in text.strip().splitlines() if line.strip()]
    for line in lines:
        if re.search(r"\.xml:\d+:\d+:", line) or line.startswith("error"):
            return line.strip()
    return lines[0].strip() if lines else "(no message)"


def render_glint(args, path, out):
    # `-D spp` as Mitsuba's render_documentation_images.py passes it (some scenes name $spp
    # with no default); --spp sets the count where a scene writes its own.
    run = subprocess.run([args.glint, "render", path, "-D", f"spp={args.spp}", "--spp", str(args.spp), "--seed",
                          "0", "--threads", str(args.threads), "-q", "-o", out], capture_output=True, text=True)
    warnings = [line.strip() for line in run.stderr.splitlines() if "warning" in line.lower()]
    return run.returncode == 0, first_error(run.stderr + run.stdout), warnings


def render_mitsuba(args, path, image, variance):
    run = subprocess.run([args.mitsuba_python, "-c", MITSUBA_RENDER, path, str(args.reference_spp), "1",
                          str(args.threads), image, variance, str(args.spp)], capture_output=True, text=True)
    if run.returncode != 0:
        lines = [line for line in (run.stderr or run.stdout).strip().splitlines() if line.strip()]
        return False, lines[-1] if lines else f"exit status {run.returncode}"
    return True, json.loads(run.stdout.strip().splitlines()[-1])["spp"]


def mitsuba_loads(args, path):
    """Whether Mitsuba's scalar_rgb loads the scene, or its last line of error."""
    run = subprocess.run([args.mitsuba_python, "-c", MITSUBA_LOAD, path, str(args.reference_spp)],
                         capture_output=True, text=True)
    if run.returncode == 0:
        return "Mitsuba scalar_rgb loads it"
    lines = [line.strip() for line in run.stderr.strip().splitlines() if line.strip()]
    # Its last line, without the parser's preamble: "At FILE (line L, col C): failed to …: [Plugin] why".
    last = re.sub(r"^RuntimeError: \[[^]]*\] ", "", lines[-1]) if lines else str(run.returncode)
    return f"Mitsuba scalar_rgb fails too: {last}"


def z_test(args, image, reference, variance):
    run = subprocess.run([args.glint, "compare", image, reference, "--variance", variance, "--json"],
                         capture_output=True, text=True)
    if run.returncode not in (0, 1):
        return None, first_error(run.stderr)
    return json.loads(run.stdout), None


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("docs_scenes", help="mitsuba-data's docs/scenes, with ../../common beside it")
    parser.add_argument("--glint", default=os.path.join(ROOT, "target", "release", "glint"))
    parser.add_argument("--mitsuba-python", help="a Python with Mitsuba 3 (scalar_rgb): adds the Z-test")
    parser.add_argument("--scale", type=float, default=8, help="divide each film's size by this")
    parser.add_argument("--spp", type=int, default=64, help="glint's samples per pixel")
    parser.add_argument("--reference-spp", type=int, default=256, help="Mitsuba's samples per pixel")
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--only", nargs="*", help="only these scenes (file names without .xml)")
    parser.add_argument("--keep", help="keep the images (and the scratch scenes) in this folder")
    parser.add_argument("--json", action="store_true", help="print the results as JSON")
    args = parser.parse_args()

    docs = os.path.abspath(args.docs_scenes)
    names = sorted(n[:-4] for n in os.listdir(docs) if n.endswith(".xml"))
    if args.only:
        names = [n for n in names if n in args.only]
    scratch = args.keep or tempfile.mkdtemp(prefix="glint-docs-scenes-")
    os.makedirs(scratch, exist_ok=True)
    scenes = scratch_copy(docs, os.path.join(scratch, "scenes"), args.scale)
    images = os.path.join(scratch, "images")
    os.makedirs(images, exist_ok=True)

    rows = []
    try:
        for name in names:
            path = os.path.join(scenes, f"{name}.xml")
            row = {"scene": name}
            out = os.path.join(images, f"{name}-glint.exr")
            loaded, message, warnings = render_glint(args, path, out)
            row["glint"] = "renders" if loaded else "refused"
            if not loaded:
                row["message"] = message.replace(scenes, docs)
                if args.mitsuba_python:
                    row["mitsuba"] = mitsuba_loads(args, path).replace(scenes, docs)
            row["warnings"] = [w.replace(scenes, docs) for w in warnings]
            if loaded and args.mitsuba_python:
                reference = os.path.join(images, f"{name}-mitsuba.exr")
                variance = os.path.join(images, f"{name}-mitsuba-var.exr")
                ok, result = render_mitsuba(args, path, reference, variance)
                if not ok:
                    row["mitsuba"] = f"Mitsuba scalar_rgb does not render it: {result}"
                else:
                    row["mitsuba_spp"] = result
                    report, error = z_test(args, out, reference, variance)
                    if error:
                        row["z_test"] = error
                    else:
                        row["z_test"] = report["z_test"]
                        row["mean_ratio"] = report["mean_ratio"]
            rows.append(row)
            if not args.json:
                print(summary_line(row), file=sys.stderr, flush=True)
    finally:
        if not args.keep:
            shutil.rmtree(scratch, ignore_errors=True)

    if args.json:
        print(json.dumps(rows, indent=1))
        return
    print_table(rows, args)


def z_verdict(z):
    """(passed, "pass (99.93 %)") from `glint compare --json`'s z_test, or its error."""
    if not isinstance(z, dict):
        return False, str(z)
    return z["passed"], f"{'pass' if z['passed'] else 'FAIL'} ({100 * z['fraction_passed']:.2f} %)"


def summary_line(row):
    text = f"{row['scene']}: {row['glint']}"
    if "message" in row:
        text += f": {row['message']}"
    if "mitsuba" in row:
        text += f"; {row['mitsuba']}"
    if "z_test" in row:
        text += f"; Z-test {z_verdict(row['z_test'])[1]}"
    if "mean_ratio" in row:
        text += "; means glint/Mitsuba " + ", ".join(f"{r:.4f}" for r in row["mean_ratio"])
    return text


def print_table(rows, args):
    rendered = [r for r in rows if r["glint"] == "renders"]
    print(f"{len(rendered)} of {len(rows)} scenes render, {len(rows) - len(rendered)} are refused "
          f"(films / {args.scale:g}, glint {args.spp} spp)")
    if args.mitsuba_python:
        tested = [r for r in rendered if "z_test" in r]
        passed = [r for r in tested if z_verdict(r["z_test"])[0]]
        print(f"Z-test against Mitsuba scalar_rgb at {args.reference_spp} spp: {len(passed)} of "
              f"{len(tested)} pass")
    print()
    print("| scene | glint | Mitsuba: Z-test, or whether it loads a scene glint refuses "
          "| means glint / Mitsuba (R, G, B) | glint's message |")
    print("| --- | --- | --- | --- | --- |")
    for r in rows:
        z = z_verdict(r["z_test"])[1] if "z_test" in r else r.get("mitsuba", "")
        ratio = ", ".join(f"{x:.4f}" for x in r.get("mean_ratio", []))
        message = re.sub(r"^.*?/docs/scenes/", "", r.get("message", "")).replace("|", "\\|")
        print(f"| {r['scene']} | {r['glint']} | {z} | {ratio} | {message} |")


if __name__ == "__main__":
    main()
