#!/usr/bin/env python3
"""Time to first pixel for a large mesh through each scene reader: the Stanford dragon
(871,414 triangles, ../shared/meshes) placed by a native TOML scene, a Mitsuba 3 XML scene,
a pbrt-v4 scene (`plymesh`) and a glTF 2.0 binary (.glb, written here from the PLY), each
rendered by glint at 8x8 pixels, 1 spp (reading, building the BVH, one pass); and Mitsuba 3
loading the same XML (`mi.load_file`, which builds its own acceleration structure) and
rendering it at 8x8, 1 spp, when its Python is given.

  python3 benchmarks/load_scenes.py --glint target/release/glint [--mitsuba-python PY] [--rounds 5]

Each figure is the median of the rounds' wall times; readers alternate within a round.
"""

import argparse
import gzip
import json
import os
import statistics
import struct
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
DRAGON = os.path.join(HERE, "..", "..", "shared", "meshes", "stanford_dragon.ply.gz")

CAMERA = dict(position=[-0.2, 0.2, 0.3], target=[0.0, 0.12, 0.0])


def write_scenes(directory):
    ply = os.path.join(directory, "dragon.ply")
    with gzip.open(DRAGON, "rb") as f, open(ply, "wb") as out:
        data = f.read()
        out.write(data)
    p, t = CAMERA["position"], CAMERA["target"]
    with open(os.path.join(directory, "dragon.toml"), "w") as f:
        f.write(f"""[camera]
position = {p}
look_at = {t}
resolution = [8, 8]
[render]
integrator = "path"
[environment]
background = [1, 1, 1]
[materials.clay]
type = "diffuse"
reflectance = [0.5, 0.5, 0.5]
[[shapes]]
type = "mesh"
file = "dragon.ply"
material = "clay"
""")
    with open(os.path.join(directory, "dragon.xml"), "w") as f:
        f.write(f"""<scene version="3.0.0">
<integrator type="path"/>
<sensor type="perspective"><float name="fov" value="45"/>
<transform name="to_world"><lookat origin="{','.join(map(str, p))}" target="{','.join(map(str, t))}" up="0,1,0"/></transform>
<film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/></film>
<sampler type="independent"><integer name="sample_count" value="1"/></sampler></sensor>
<emitter type="constant"/>
<shape type="ply"><string name="filename" value="dragon.ply"/><bsdf type="diffuse"/></shape>
</scene>
""")
    with open(os.path.join(directory, "dragon.pbrt"), "w") as f:
        f.write(f"""Scale -1 1 1
LookAt {' '.join(map(str, p))}  {' '.join(map(str, t))}  0 1 0
Camera "perspective" "float fov" 45
Film "rgb" "integer xresolution" 8 "integer yresolution" 8
Sampler "independent" "integer pixelsamples" 1
WorldBegin
LightSource "infinite" "rgb L" [ 1 1 1 ]
Material "diffuse"
Shape "plymesh" "string filename" "dragon.ply"
""")
    write_glb(data, os.path.join(directory, "dragon.glb"))


def write_glb(ply, path):
    """The PLY's vertices and faces as one glTF primitive (no camera: glint frames it)."""
    header_end = ply.index(b"end_header\n") + len(b"end_header\n")
    header = ply[:header_end].decode()
    vertices = int(header.split("element vertex ")[1].split()[0])
    faces = int(header.split("element face ")[1].split()[0])
    body = ply[header_end:]
    positions = body[: 12 * vertices]
    indices = bytearray()
    offset = 12 * vertices
    for i in range(faces):
        indices += body[offset + 13 * i + 1: offset + 13 * i + 13]
    floats = struct.unpack(f"<{3 * vertices}f", positions)
    lo = [min(floats[c::3]) for c in range(3)]
    hi = [max(floats[c::3]) for c in range(3)]
    bin_ = bytes(positions) + bytes(indices)
    doc = {
        "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
        "buffers": [{"byteLength": len(bin_)}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": len(positions)},
                        {"buffer": 0, "byteOffset": len(positions), "byteLength": len(indices)}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": vertices, "type": "VEC3", "min": lo, "max": hi},
                      {"bufferView": 1, "componentType": 5125, "count": 3 * faces, "type": "SCALAR"}],
    }
    text = json.dumps(doc).encode()
    text += b" " * (-len(text) % 4)
    bin_ += b"\0" * (-len(bin_) % 4)
    with open(path, "wb") as f:
        f.write(b"glTF" + struct.pack("<II", 2, 12 + 8 + len(text) + 8 + len(bin_)))
        f.write(struct.pack("<I", len(text)) + b"JSON" + text + struct.pack("<I", len(bin_)) + b"BIN\0" + bin_)


def timed(command):
    start = time.perf_counter()
    subprocess.run(command, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return time.perf_counter() - start


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--glint", required=True)
    parser.add_argument("--mitsuba-python")
    parser.add_argument("--rounds", type=int, default=5)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as directory:
        write_scenes(directory)
        runs = {}
        for name in ["dragon.toml", "dragon.xml", "dragon.pbrt", "dragon.glb"]:
            out = os.path.join(directory, name + ".exr")
            runs[f"glint {name}"] = [args.glint, "render", os.path.join(directory, name), "-o", out, "--spp", "1", "--width", "8", "--height", "8"]
        if args.mitsuba_python:
            script = ("import mitsuba as mi, sys; mi.set_variant('llvm_ad_rgb'); "
                      "s = mi.load_file(sys.argv[1]); mi.render(s, spp=1)")
            runs["Mitsuba 3 llvm_ad_rgb dragon.xml"] = [args.mitsuba_python, "-c", script, os.path.join(directory, "dragon.xml")]
            # Its import and JIT start-up alone, to tell them from loading.
            runs["Mitsuba 3 llvm_ad_rgb start-up only"] = [args.mitsuba_python, "-c", "import mitsuba as mi; mi.set_variant('llvm_ad_rgb')"]
        times = {name: [] for name in runs}
        for _ in range(args.rounds):
            for name, command in runs.items():
                times[name].append(timed(command))
        for name, ts in times.items():
            print(f"{name:40s} median {statistics.median(ts):.3f} s  (min {min(ts):.3f}, max {max(ts):.3f})")


if __name__ == "__main__":
    sys.exit(main())
