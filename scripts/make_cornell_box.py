#!/usr/bin/env python3
"""Writes scenes/cornell-box.toml from ../shared/scenes/cbox.json (the renderer-neutral Cornell
box), so glint renders exactly the scene of the Mitsuba 3 reference. Standard library only.

Usage: python3 scripts/make_cornell_box.py [path/to/cbox.json]
"""
import json
import os
import sys

here = os.path.dirname(os.path.abspath(__file__))
source = sys.argv[1] if len(sys.argv) > 1 else os.path.join(here, "..", "..", "shared", "scenes", "cbox.json")
d = json.load(open(source))
cam = d["camera"]
out = [f"""# The Cornell box, the same scene as ../shared/scenes/cbox.json (and Mitsuba's cbox.xml):
# geometry from the published Cornell measurements in millimetres, every quad split into
# triangles (v0, v1, v2) and (v0, v2, v3), flat-shaded; two-sided Lambertian surfaces with the
# RGB albedos given; a one-sided area light emitting downward; a pinhole camera at
# (278, 273, -800) looking along +z with a 39.3077° vertical field of view. Path traced with
# unbounded depth and Russian roulette from depth 5, as the Mitsuba 3 reference
# ../shared/references/cbox_256.exr was rendered.
#
#   glint render scenes/cornell-box.toml -o cornell.png
# Generated from cbox.json by scripts/make_cornell_box.py.

[camera]
position = {json.dumps(cam["origin"])}
look_at = {json.dumps(cam["target"])}
up = {json.dumps(cam["up"])}
fov = {cam["fov_y_deg"]}
resolution = [256, 256]

[render]
integrator = "path"
spp = 256
max_depth = -1
rr_depth = 5
"""]
for name, m in d["materials"].items():
    out.append(f'[materials.{name}]\ntype = "diffuse"\nreflectance = {json.dumps(m["albedo"])}')
    if "radiance" in m:
        out.append(f'emission = {json.dumps(m["radiance"])}')
    out.append("")
for q in d["quads"]:
    v = ", ".join(json.dumps(p) for p in q["v"])
    out.append(f'[[shapes]]\ntype = "quad"\nname = "{q["name"]}"\nvertices = [{v}]\nmaterial = "{q["material"]}"\n')
target = os.path.join(here, "..", "scenes", "cornell-box.toml")
with open(target, "w") as f:
    f.write("\n".join(out))
print(f"wrote {target}")
