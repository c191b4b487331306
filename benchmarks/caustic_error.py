#!/usr/bin/env python3
"""Relative MSE of renders against a reference EXR, over the whole image and over the caustic
region (the reference's pixels brighter than 1, mean over RGB): the equal-time comparison of
docs/performance.md. Needs numpy and OpenEXR (pip install numpy OpenEXR).

    python3 benchmarks/caustic_error.py REFERENCE.exr RENDER.exr [RENDER.exr ...]

relMSE per pixel = mean over RGB of (render − reference)² / (reference² + 0.01)."""
import sys

import Imath
import numpy as np
import OpenEXR


def read(path):
    f = OpenEXR.InputFile(path)
    window = f.header()["dataWindow"]
    w, h = window.max.x - window.min.x + 1, window.max.y - window.min.y + 1
    channel = lambda c: np.frombuffer(f.channel(c, Imath.PixelType(Imath.PixelType.FLOAT)), dtype=np.float32)
    return np.stack([channel(c).reshape(h, w) for c in "RGB"], -1)


reference = read(sys.argv[1])
caustic = reference.mean(-1) > 1.0
print(f"caustic region: {caustic.sum()} pixels")
for path in sys.argv[2:]:
    image = read(path)
    error = ((image - reference) ** 2 / (reference ** 2 + 1e-2)).mean(-1)
    print(f"{path}: relMSE whole image {error.mean():.5f}, caustic region {error[caustic].mean():.5f}")
