#!/usr/bin/env python3
"""Makes the glTF example scenes of scenes/gltf/ (made for glint, no third-party assets),
with nothing but Python's standard library:

* spheres.glb: five spheres of glTF's metallic-roughness model (gold, polished steel, red
  paint under a clearcoat, glass with a volume, a thin tinted film) on a checkered floor
  (an embedded PNG with KHR_texture_transform); no lights and no camera, so glint frames
  it and lights it by its default white sky.
* knots.gltf: a torus knot placed three times (one mesh, three nodes: instancing) in
  textured copper, clay and emissive glow, lit by a KHR_lights_punctual spot and point
  light, seen through the file's camera; JSON with its buffer and images as data URIs.

Run from the repository: python3 scripts/gltf_models.py
"""

import base64
import json
import math
import os
import struct
import zlib

OUT = os.path.join(os.path.dirname(__file__), "..", "scenes", "gltf")


def png(width, height, pixel):
    """An 8-bit RGB PNG of pixel(x, y) -> (r, g, b)."""
    rows = b"".join(b"\0" + bytes(c for x in range(width) for c in pixel(x, y)) for y in range(height))

    def chunk(kind, data):
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body) & 0xFFFFFFFF)

    header = struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(rows, 9)) + chunk(b"IEND", b"")


class Document:
    """A glTF document whose accessors share one buffer."""

    def __init__(self):
        self.bin = bytearray()
        self.json = {"asset": {"version": "2.0", "generator": "glint scripts/gltf_models.py"},
                     "bufferViews": [], "accessors": [], "meshes": [], "materials": [], "nodes": [],
                     "images": [], "textures": [], "samplers": []}

    def view(self, data):
        while len(self.bin) % 4:
            self.bin.append(0)
        self.json["bufferViews"].append({"buffer": 0, "byteOffset": len(self.bin), "byteLength": len(data)})
        self.bin += data
        return len(self.json["bufferViews"]) - 1

    def accessor(self, values, kind, component="f"):
        flat = [c for v in values for c in (v if isinstance(v, (list, tuple)) else [v])]
        code = {"f": 5126, "I": 5125}[component]
        accessor = {"bufferView": self.view(struct.pack("<%d%s" % (len(flat), component), *flat)),
                    "componentType": code, "count": len(values), "type": kind}
        if kind == "VEC3":
            accessor["min"] = [min(v[i] for v in values) for i in range(3)]
            accessor["max"] = [max(v[i] for v in values) for i in range(3)]
        self.json["accessors"].append(accessor)
        return len(self.json["accessors"]) - 1

    def mesh(self, positions, normals, uvs, triangles, material):
        primitive = {"attributes": {"POSITION": self.accessor(positions, "VEC3"),
                                    "NORMAL": self.accessor(normals, "VEC3"),
                                    "TEXCOORD_0": self.accessor(uvs, "VEC2")},
                     "indices": self.accessor([i for t in triangles for i in t], "SCALAR", "I"),
                     "material": material}
        self.json["meshes"].append({"primitives": [primitive]})
        return len(self.json["meshes"]) - 1

    def image(self, data, embed_uri):
        if embed_uri:
            self.json["images"].append({"uri": "data:image/png;base64," + base64.b64encode(data).decode()})
        else:
            self.json["images"].append({"bufferView": self.view(data), "mimeType": "image/png"})
        self.json["textures"].append({"source": len(self.json["images"]) - 1, "sampler": 0})
        return len(self.json["textures"]) - 1

    def material(self, **m):
        self.json["materials"].append(m)
        return len(self.json["materials"]) - 1

    def node(self, **n):
        self.json["nodes"].append(n)
        return len(self.json["nodes"]) - 1


def sphere(radius, rings=32, segments=64):
    positions, normals, uvs, triangles = [], [], [], []
    for j in range(rings + 1):
        theta = math.pi * j / rings
        for i in range(segments + 1):
            phi = 2 * math.pi * i / segments
            n = (math.sin(theta) * math.cos(phi), math.cos(theta), -math.sin(theta) * math.sin(phi))
            positions.append(tuple(radius * c for c in n))
            normals.append(n)
            uvs.append((i / segments, j / rings))
    for j in range(rings):
        for i in range(segments):
            a, b = j * (segments + 1) + i, (j + 1) * (segments + 1) + i
            if j > 0:  # the first row's other triangle is a point at the pole
                triangles.append((a, b, a + 1))
            if j < rings - 1:
                triangles.append((a + 1, b, b + 1))
    return positions, normals, uvs, triangles


def torus_knot(p=2, q=3, radius=1.0, tube=0.28, segments=320, sides=20):
    """A (p, q) torus knot swept by a circle, with a parallel-transport-free Frenet frame."""
    def centre(t):
        r = radius * (2 + math.cos(q * t)) / 3
        return (r * math.cos(p * t), radius * math.sin(q * t) / 3 * 1.5, r * math.sin(p * t))

    positions, normals, uvs, triangles = [], [], [], []
    for i in range(segments + 1):
        t = 2 * math.pi * i / segments
        c, c2 = centre(t), centre(t + 1e-3)
        tangent = [b - a for a, b in zip(c, c2)]
        length = math.sqrt(sum(x * x for x in tangent))
        tangent = [x / length for x in tangent]
        up = (0.0, 1.0, 0.0)
        side = [tangent[1] * up[2] - tangent[2] * up[1], tangent[2] * up[0] - tangent[0] * up[2], tangent[0] * up[1] - tangent[1] * up[0]]
        s = math.sqrt(sum(x * x for x in side))
        side = [x / s for x in side]
        binormal = [side[1] * tangent[2] - side[2] * tangent[1], side[2] * tangent[0] - side[0] * tangent[2], side[0] * tangent[1] - side[1] * tangent[0]]
        for k in range(sides + 1):
            a = 2 * math.pi * k / sides
            n = [math.cos(a) * s_ + math.sin(a) * b_ for s_, b_ in zip(side, binormal)]
            positions.append(tuple(ci + tube * ni for ci, ni in zip(c, n)))
            normals.append(tuple(n))
            uvs.append((8 * i / segments, k / sides))
    for i in range(segments):
        for k in range(sides):
            a, b = i * (sides + 1) + k, (i + 1) * (sides + 1) + k
            triangles += [(a, b, a + 1), (a + 1, b, b + 1)]
    return positions, normals, uvs, triangles


def floor(size):
    positions = [(-size, 0, -size), (size, 0, -size), (size, 0, size), (-size, 0, size)]
    return positions, [(0, 1, 0)] * 4, [(0, 0), (1, 0), (1, 1), (0, 1)], [(0, 2, 1), (0, 3, 2)]


def spheres():
    doc = Document()
    doc.json["samplers"].append({"wrapS": 10497, "wrapT": 10497})
    checks = doc.image(png(64, 64, lambda x, y: (210, 205, 195) if (x // 8 + y // 8) % 2 else (70, 72, 80)), embed_uri=False)
    floor_material = doc.material(name="checkered floor", pbrMetallicRoughness={
        "baseColorTexture": {"index": checks, "extensions": {"KHR_texture_transform": {"scale": [4, 4]}}},
        "metallicFactor": 0.0, "roughnessFactor": 0.9})
    materials = [
        doc.material(name="gold", pbrMetallicRoughness={"baseColorFactor": [1.0, 0.766, 0.336, 1], "metallicFactor": 1.0, "roughnessFactor": 0.3}),
        doc.material(name="steel", pbrMetallicRoughness={"baseColorFactor": [0.56, 0.57, 0.58, 1], "metallicFactor": 1.0, "roughnessFactor": 0.05}),
        doc.material(name="clearcoat paint", pbrMetallicRoughness={"baseColorFactor": [0.7, 0.05, 0.04, 1], "metallicFactor": 0.0, "roughnessFactor": 0.6},
                     extensions={"KHR_materials_clearcoat": {"clearcoatFactor": 1.0, "clearcoatRoughnessFactor": 0.05}}),
        doc.material(name="glass", pbrMetallicRoughness={"baseColorFactor": [0.9, 1.0, 0.95, 1], "metallicFactor": 0.0, "roughnessFactor": 0.0},
                     extensions={"KHR_materials_transmission": {"transmissionFactor": 1.0}, "KHR_materials_ior": {"ior": 1.5},
                                 "KHR_materials_volume": {"thicknessFactor": 1.0}}),
        doc.material(name="blue film", pbrMetallicRoughness={"baseColorFactor": [0.3, 0.5, 1.0, 1], "metallicFactor": 0.0, "roughnessFactor": 0.2},
                     extensions={"KHR_materials_transmission": {"transmissionFactor": 0.8}}),
    ]
    roots = [doc.node(name="floor", mesh=doc.mesh(*floor(5), floor_material))]
    ball = sphere(0.8)
    for k, material in enumerate(materials):
        roots.append(doc.node(name=doc.json["materials"][material]["name"], mesh=doc.mesh(*ball, material),
                              translation=[(k - 2) * 1.9, 0.8, 0]))
    doc.json["scene"] = 0
    doc.json["scenes"] = [{"nodes": roots}]
    doc.json["extensionsUsed"] = ["KHR_texture_transform", "KHR_materials_clearcoat", "KHR_materials_transmission",
                                  "KHR_materials_ior", "KHR_materials_volume"]
    doc.json["buffers"] = [{"byteLength": len(doc.bin)}]
    write_glb(os.path.join(OUT, "spheres.glb"), doc)


def knots():
    doc = Document()
    doc.json["samplers"].append({"wrapS": 10497, "wrapT": 10497})
    stripes = doc.image(png(64, 8, lambda x, y: (235, 150, 90) if (x // 8) % 2 else (150, 70, 40)), embed_uri=True)
    # Roughness (green) in bands, metal (blue) everywhere.
    bands = doc.image(png(64, 8, lambda x, y: (0, 40 if (x // 8) % 2 else 150, 255)), embed_uri=True)
    copper = doc.material(name="striped copper", pbrMetallicRoughness={
        "baseColorTexture": {"index": stripes}, "metallicRoughnessTexture": {"index": bands}})
    clay = doc.material(name="clay", pbrMetallicRoughness={"baseColorFactor": [0.75, 0.72, 0.65, 1], "metallicFactor": 0.0, "roughnessFactor": 1.0})
    glow = doc.material(name="glow", emissiveFactor=[1.0, 0.45, 0.15], extensions={"KHR_materials_emissive_strength": {"emissiveStrength": 2.5}},
                        pbrMetallicRoughness={"baseColorFactor": [0.1, 0.1, 0.1, 1], "metallicFactor": 0.0})
    knot = torus_knot()
    copper_knot = doc.mesh(*knot, copper)
    glow_knot = doc.mesh(*knot, glow)
    roots = [doc.node(name="floor", mesh=doc.mesh(*floor(12), clay))]
    # The copper knot placed twice (one mesh: instanced), the glowing one once.
    roots.append(doc.node(name="group", translation=[0, 1.1, 0], children=[
        doc.node(name="left knot", mesh=copper_knot, translation=[-2.4, 0, 0], rotation=[0.0, 0.3826834, 0.0, 0.9238795]),
        doc.node(name="right knot", mesh=copper_knot, translation=[2.4, 0, 0], scale=[0.8, 0.8, 0.8]),
        doc.node(name="middle knot", mesh=glow_knot, translation=[0, 0.2, -1.5], rotation=[0.3826834, 0.0, 0.0, 0.9238795]),
    ]))
    doc.json["extensions"] = {"KHR_lights_punctual": {"lights": [
        {"type": "spot", "color": [1.0, 0.95, 0.9], "intensity": 40000.0, "spot": {"innerConeAngle": 0.35, "outerConeAngle": 0.6}},
        {"type": "point", "color": [0.6, 0.7, 1.0], "intensity": 6000.0},
    ]}}
    # The spot straight down from above, the point light at the right.
    roots.append(doc.node(name="spot", translation=[0, 8, 2], rotation=[-0.6087614, 0, 0, 0.7933533], extensions={"KHR_lights_punctual": {"light": 0}}))
    roots.append(doc.node(name="fill", translation=[5, 3, 4], extensions={"KHR_lights_punctual": {"light": 1}}))
    doc.json["cameras"] = [{"type": "perspective", "perspective": {"yfov": 0.6, "aspectRatio": 16 / 9, "znear": 0.1}}]
    # Up and in front, looking down 20°.
    roots.append(doc.node(name="camera", camera=0, translation=[0, 3.6, 9.5], rotation=[-0.1736482, 0, 0, 0.9848078]))
    doc.json["scene"] = 0
    doc.json["scenes"] = [{"nodes": roots}]
    doc.json["extensionsUsed"] = ["KHR_lights_punctual", "KHR_materials_emissive_strength"]
    doc.json["buffers"] = [{"byteLength": len(doc.bin), "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(doc.bin)).decode()}]
    with open(os.path.join(OUT, "knots.gltf"), "w") as f:
        json.dump(doc.json, f)


def write_glb(path, doc):
    text = json.dumps(doc.json).encode()
    text += b" " * (-len(text) % 4)
    binary = bytes(doc.bin) + b"\0" * (-len(doc.bin) % 4)
    with open(path, "wb") as f:
        f.write(b"glTF" + struct.pack("<II", 2, 12 + 8 + len(text) + 8 + len(binary)))
        f.write(struct.pack("<I", len(text)) + b"JSON" + text)
        f.write(struct.pack("<I", len(binary)) + b"BIN\0" + binary)


if __name__ == "__main__":
    os.makedirs(OUT, exist_ok=True)
    spheres()
    knots()
