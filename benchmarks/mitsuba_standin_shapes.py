#!/usr/bin/env python3
"""The suite's `various_shapes` scene against Mitsuba 3 itself, with stand-ins for the files
the shared copy of the suite lacks (issue 25): not a benchmark of speed, a check of
conformance that needs Mitsuba, so it lives here rather than among the tests.

The scene loads `../../serialized/`, `../../obj/` and `../../ply/rectangle_normals_uv.*` and
`../../../docs/scenes/sdfgrid/torus_sdfgrid.vol`, none of which the shared copy holds. This
script writes stand-ins into a temporary copy of the suite's layout (a textured rectangle with
normals and uv as OBJ and PLY; a 48³ torus distance grid; the serialized rectangle left out, as
nothing here writes that format), renders Mitsuba's reference and per-sample variance (the
`moment` integrator's XYZ moments) at `--reference-spp`, renders glint at the suite's budget
(2·10⁶ samples per image: 8 spp) and at `--spp`, and prints `glint compare`'s Z-test (Mitsuba's
statistics) for each.

    python3 benchmarks/mitsuba_standin_shapes.py --mitsuba-python ~/venvs/mitsuba/bin/python \
        [--glint target/release/glint] [--reference-spp 2048] [--spp 256]

Needs numpy in `--mitsuba-python`'s Python (the anchors' `mitsuba/setup.sh` makes that venv).
"""
import argparse
import os
import re
import struct
import subprocess
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCENE = os.path.normpath(
    os.path.join(ROOT, "..", "shared", "mitsuba-suite", "scenes", "various_shapes", "test_various_shapes_path.xml")
)

OBJ = """v -1 -1 0
v 1 -1 0
v 1 1 0
v -1 1 0
vn 0 0 1
vt 0 0
vt 1 0
vt 1 1
vt 0 1
f 1/1/1 2/2/1 3/3/1
f 1/1/1 3/3/1 4/4/1
"""

PLY = """ply
format ascii 1.0
element vertex 4
property float x
property float y
property float z
property float nx
property float ny
property float nz
property float u
property float v
element face 2
property list uchar int vertex_indices
end_header
-1 -1 0 0 0 1 0 0
1 -1 0 0 0 1 1 0
1 1 0 0 0 1 1 1
-1 1 0 0 0 1 0 1
3 0 1 2
3 0 2 3
"""

MITSUBA_REFERENCE = r"""
import sys
import numpy as np
import mitsuba as mi
mi.set_variant("llvm_ad_rgb")
mi.set_log_level(mi.LogLevel.Error)
path, spp, out = sys.argv[1], int(sys.argv[2]), sys.argv[3]
scene = mi.load_file(path, integrator="path", spp=spp)
image = np.array(mi.render(scene, spp=spp, seed=0))
# The moment integrator's channels: RGB, then the first and second moments in XYZ.
variance = np.maximum(image[..., 6:9] - image[..., 3:6] ** 2, 0)
mi.Bitmap(image[..., :3].astype(np.float32).copy(), mi.Bitmap.PixelFormat.RGB).write(out + ".exr")
mi.Bitmap(variance.astype(np.float32).copy(), mi.Bitmap.PixelFormat.RGB).write(out + "_var.exr")
"""


def torus_vol(path, n=48, major=0.3, minor=0.12):
    """A Mitsuba .vol file of the torus's signed distances on n³ samples over the unit cube."""
    values = bytearray()
    for k in range(n):
        for j in range(n):
            for i in range(n):
                x, y, z = (i / (n - 1) - 0.5, j / (n - 1) - 0.5, k / (n - 1) - 0.5)
                ring = ((x * x + y * y) ** 0.5 - major) ** 2 + z * z
                values += struct.pack("<f", ring**0.5 - minor)
    header = b"VOL" + bytes([3]) + struct.pack("<iiiii", 1, n, n, n, 1) + struct.pack("<6f", 0, 0, 0, 1, 1, 1)
    with open(path, "wb") as f:
        f.write(header + values)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--mitsuba-python", required=True)
    parser.add_argument("--glint", default=os.path.join(ROOT, "target", "release", "glint"))
    parser.add_argument("--reference-spp", type=int, default=2048)
    parser.add_argument("--spp", type=int, default=256)
    args = parser.parse_args()

    with tempfile.TemporaryDirectory() as work:
        for folder in ["scenes/various_shapes", "obj", "ply", "sdf"]:
            os.makedirs(os.path.join(work, folder))
        with open(os.path.join(work, "obj", "rectangle_normals_uv.obj"), "w") as f:
            f.write(OBJ)
        with open(os.path.join(work, "ply", "rectangle_normals_uv.ply"), "w") as f:
            f.write(PLY)
        torus_vol(os.path.join(work, "sdf", "torus_sdfgrid.vol"))
        with open(SCENE) as f:
            text = f.read()
        text = re.sub(r'\s*<shape type="serialized">.*?</shape>', "", text, flags=re.S)
        text = text.replace("../../../docs/scenes/sdfgrid/", "../../sdf/")
        scene = os.path.join(work, "scenes", "various_shapes", "standin_path.xml")
        with open(scene, "w") as f:
            f.write(text)

        reference = os.path.join(work, "mitsuba")
        print(f"Mitsuba 3 reference at {args.reference_spp} spp ...", flush=True)
        subprocess.run(
            [args.mitsuba_python, "-c", MITSUBA_REFERENCE, scene, str(args.reference_spp), reference], check=True
        )
        for spp in [8, args.spp]:
            image = os.path.join(work, f"glint-{spp}.exr")
            subprocess.run(
                [args.glint, "render", scene, "-D", f"spp={spp}", "-D", "integrator=path", "--seed", "0", "-o", image],
                check=True,
                capture_output=True,
            )
            result = subprocess.run(
                [args.glint, "compare", image, reference + ".exr", "--variance", reference + "_var.exr", "--spp", str(spp)],
                check=True,
                capture_output=True,
                text=True,
            )
            z_test = [line for line in result.stdout.splitlines() if line.startswith("Z-test")]
            print(f"glint at {spp} spp: {z_test[0] if z_test else result.stdout}")


if __name__ == "__main__":
    main()
