#!/usr/bin/env python3
"""Writes scenes/textures/uv-grid.png: a 128x128 test image (colour ramps in u and v, grid lines
every 16 pixels, a dot at the top-left), glint's own example texture. Standard library only."""
import os
import struct
import zlib

size = 128
rows = []
for y in range(size):
    row = bytearray([0])  # filter type 0 for each scanline
    for x in range(size):
        u, v = x / (size - 1), 1 - y / (size - 1)
        r, g, b = int(255 * u), int(255 * v), 96
        if x % 16 == 0 or y % 16 == 0:
            r, g, b = 20, 20, 20
        if (x - 16) ** 2 + (y - 16) ** 2 < 36:
            r, g, b = 255, 255, 255
        row += bytes([r, g, b])
    rows.append(bytes(row))

def chunk(kind, data):
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", size, size, 8, 2, 0, 0, 0))
png += chunk(b"IDAT", zlib.compress(b"".join(rows), 9)) + chunk(b"IEND", b"")
out = os.path.join(os.path.dirname(__file__), "..", "scenes", "textures", "uv-grid.png")
with open(out, "wb") as f:
    f.write(png)
print(f"wrote {out}")
