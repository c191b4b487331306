#!/usr/bin/env python3
"""scenes/fog.toml against Mitsuba 3 on the same scene: glint's `volpath` and Mitsuba's
`volpath` (llvm_ad_rgb) render the haze, the floor, the glass ball and the clay box at the same
resolution and samples per pixel; the script reports each one's render time (Mitsuba's without
its import and start-up, which it times apart) and samples per second.

The Mitsuba scene is written here from the same numbers. Two differences remain, so the
figures compare cost per sample, not images:
* Mitsuba's spot falls off linearly in angle over `beam_width` to `cutoff_angle`, glint's by
  pbrt's smoothstep of the cosine;
* Mitsuba samples emitters uniformly here as glint samples them by power (two delta lights).

  python3 benchmarks/compare_fog.py --glint target/release/glint --mitsuba-python ~/venvs/mitsuba/bin/python [--spp 64] [--rounds 3]
"""

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
SCENE = os.path.join(HERE, "..", "scenes", "fog.toml")

XML = """<scene version="3.0.0">
<integrator type="volpath"><integer name="max_depth" value="12"/><integer name="rr_depth" value="5"/></integrator>
<medium type="homogeneous" id="haze">
  <rgb name="sigma_t" value="0.09"/><rgb name="albedo" value="0.9"/>
  <phase type="hg"><float name="g" value="0.5"/></phase>
</medium>
<sensor type="perspective">
  <float name="fov" value="40"/><string name="fov_axis" value="y"/>
  <transform name="to_world"><lookat origin="0, 1.6, 6.5" target="0, 1.1, 0" up="0, 1, 0"/></transform>
  <ref id="haze"/>
  <sampler type="independent"><integer name="sample_count" value="{spp}"/></sampler>
  <film type="hdrfilm"><integer name="width" value="{width}"/><integer name="height" value="{height}"/>
    <rfilter type="box"/></film>
</sensor>
<emitter type="spot">
  <transform name="to_world"><lookat origin="0.8, 9.5, 1.0" target="0.73, 8.5, 0.93" up="0, 0, 1"/></transform>
  <rgb name="intensity" value="200, 180, 150"/>
  <float name="cutoff_angle" value="9"/><float name="beam_width" value="7"/>
</emitter>
<emitter type="point">
  <point name="position" x="-3" y="3" z="9"/>
  <rgb name="intensity" value="10.5, 13.5, 21"/>
</emitter>
<shape type="cube">
  <transform name="to_world"><scale x="6" y="2.55" z="7"/><translate x="0" y="2.05" z="1"/></transform>
  <bsdf type="null"/>
  <ref name="interior" id="haze"/>
</shape>
<shape type="rectangle">
  <transform name="to_world"><scale x="6" y="7"/><rotate x="1" angle="-90"/><translate z="1"/></transform>
  <bsdf type="twosided"><bsdf type="diffuse"><rgb name="reflectance" value="0.6, 0.58, 0.55"/></bsdf></bsdf>
  <ref name="interior" id="haze"/><ref name="exterior" id="haze"/>
</shape>
<shape type="sphere">
  <point name="center" x="0.1" y="0.8" z="0.3"/><float name="radius" value="0.8"/>
  <bsdf type="dielectric"><float name="int_ior" value="1.5"/><float name="ext_ior" value="1.0"/></bsdf>
  <ref name="exterior" id="haze"/>
</shape>
<shape type="cube">
  <transform name="to_world"><scale value="0.5"/><translate x="-1.7" y="0.5" z="-0.5"/></transform>
  <bsdf type="diffuse"><rgb name="reflectance" value="0.75, 0.3, 0.2"/></bsdf>
  <ref name="interior" id="haze"/><ref name="exterior" id="haze"/>
</shape>
</scene>
"""

MITSUBA = r"""
import sys, time
import numpy as np
import mitsuba as mi
mi.set_variant('llvm_ad_rgb')
scene = mi.load_file(sys.argv[1])
np.array(mi.render(scene, seed=0))  # kernels compiled; numpy forces the lazy evaluation
start = time.perf_counter()
image = mi.render(scene, seed=1)
pixels = np.array(image)
print(time.perf_counter() - start, pixels.mean())
mi.util.write_bitmap(sys.argv[2], image)
"""


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--glint", required=True)
    parser.add_argument("--mitsuba-python", required=True)
    parser.add_argument("--spp", type=int, default=64)
    parser.add_argument("--width", type=int, default=320)
    parser.add_argument("--rounds", type=int, default=3)
    args = parser.parse_args()
    height = args.width * 400 // 640
    with tempfile.TemporaryDirectory() as directory:
        xml = os.path.join(directory, "fog.xml")
        with open(xml, "w") as f:
            f.write(XML.format(spp=args.spp, width=args.width, height=height))
        glint_times, mitsuba_times = [], []
        for _ in range(args.rounds):
            start = time.perf_counter()
            subprocess.run([args.glint, "render", SCENE, "-o", os.path.join(directory, "glint.exr"), "--spp", str(args.spp),
                            "--width", str(args.width), "--height", str(height), "--sampler", "independent"],
                           check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            glint_times.append(time.perf_counter() - start)
            out = subprocess.run([args.mitsuba_python, "-c", MITSUBA, xml, os.path.join(directory, "mitsuba.exr")],
                                 check=True, capture_output=True, text=True)
            seconds, mean = out.stdout.strip().splitlines()[-1].split()
            mitsuba_times.append(float(seconds))
            mitsuba_mean = float(mean)
        samples = args.width * height * args.spp
        g, m = statistics.median(glint_times), statistics.median(mitsuba_times)
        print(f"{args.width}x{height}, {args.spp} spp, medians of {args.rounds}")
        print(f"glint volpath (whole command): {g:.3f} s, {samples / g / 1e6:.2f} M samples/s")
        print(f"Mitsuba 3 volpath llvm_ad_rgb (render only): {m:.3f} s, {samples / m / 1e6:.2f} M samples/s")
        print(f"glint / Mitsuba samples per second: {m / g:.2f}x")
        glint_mean = subprocess.run([args.mitsuba_python, "-c", "import sys, numpy as np, mitsuba as mi; mi.set_variant('scalar_rgb'); print(np.array(mi.Bitmap(sys.argv[1])).mean())", os.path.join(directory, "glint.exr")], check=True, capture_output=True, text=True).stdout.strip()
        print(f"image means: glint {float(glint_mean):.5f}, Mitsuba {mitsuba_mean:.5f} (the spots' profiles differ)")


if __name__ == "__main__":
    sys.exit(main())
