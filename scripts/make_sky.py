#!/usr/bin/env python3
"""Writes scenes/textures/sky.hdr: a procedural sky as an equirectangular Radiance HDR image
(512 x 256, RGBE in run-length-encoded scanlines, written as literal runs): a blue gradient brightening toward the horizon, a
grey-brown ground below it, and a small sun 35 degrees above the horizon, 400 times as bright
as the sky. Used by scenes/sky.toml. Needs only the Python standard library."""
import math
import os

W, H = 512, 256
SUN_ELEVATION = math.radians(35)
SUN_AZIMUTH = math.radians(-40)
SUN_RADIUS = math.radians(1.6)


def rgbe(r, g, b):
    m = max(r, g, b)
    if m < 1e-32:
        return bytes([0, 0, 0, 0])
    e = math.frexp(m)[1]
    scale = 256.0 / 2.0 ** e * (1 - 1e-7)
    return bytes([int(r * scale), int(g * scale), int(b * scale), e + 128])


def radiance(x, y):
    # Mitsuba's convention: v = acos(d.y)/pi from the top; u = atan2(d.x, -d.z)/(2 pi).
    theta = math.pi * (y + 0.5) / H
    phi = 2 * math.pi * (x + 0.5) / W
    d = (math.sin(theta) * math.sin(phi), math.cos(theta), -math.sin(theta) * math.cos(phi))
    elevation = math.asin(max(-1.0, min(1.0, d[1])))
    sun = (math.cos(SUN_ELEVATION) * math.sin(SUN_AZIMUTH), math.sin(SUN_ELEVATION),
           -math.cos(SUN_ELEVATION) * math.cos(SUN_AZIMUTH))
    angle = math.acos(max(-1.0, min(1.0, sum(a * b for a, b in zip(d, sun)))))
    if angle < SUN_RADIUS:
        return (420.0, 400.0, 360.0)
    if elevation < 0:
        return (0.25, 0.22, 0.18)
    t = 1 - elevation / (math.pi / 2)
    glow = 0.6 * math.exp(-angle * 3)
    return (0.25 + 0.6 * t * t + glow, 0.45 + 0.5 * t * t + glow * 0.9, 0.95 + 0.2 * t + glow * 0.7)


here = os.path.dirname(os.path.abspath(__file__))
target = os.path.join(here, "..", "scenes", "textures", "sky.hdr")
with open(target, "wb") as f:
    f.write(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n")
    f.write(f"-Y {H} +X {W}\n".encode())
    for y in range(H):
        pixels = [rgbe(*radiance(x, y)) for x in range(W)]
        # New-style scanline: a header, then each channel on its own in literal runs of ≤ 128.
        f.write(bytes([2, 2, W >> 8, W & 255]))
        for channel in range(4):
            values = bytes(p[channel] for p in pixels)
            for start in range(0, W, 128):
                chunk = values[start:start + 128]
                f.write(bytes([len(chunk)]) + chunk)
