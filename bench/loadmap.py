"""Reads a load map (`pvrt render --load-map PREFIX` writes PREFIX.exr: the deterministic work of every pixel,
rays + intersection tests + shading operations) into a numpy array, rows top to bottom.

OpenImageIO's `oiiotool --dumpdata` prints every pixel as text; that is the one reader of EXR this machine has
for Debian's python3 (no OpenEXR or OpenImageIO module), and it keeps the bench free of new dependencies.
"""
import re
import subprocess

import numpy as np

PIXEL = re.compile(rb"Pixel \((\d+), (\d+)\): ([-\d.eE+]+)")  # R of R G B (all three equal)


def read(path):
    """The work map of PREFIX.exr as a float64 array of shape (height, width)."""
    out = subprocess.run(["oiiotool", "--dumpdata", path], capture_output=True, check=True).stdout
    head = re.search(rb":\s+(\d+) x\s+(\d+),", out)
    if not head:
        raise ValueError("%s: no image size in oiiotool's output" % path)
    w, h = int(head[1]), int(head[2])
    m = np.zeros((h, w))
    found = 0
    for x, y, v in PIXEL.findall(out):
        m[int(y), int(x)] = float(v)
        found += 1
    if found != w * h:
        raise ValueError("%s: %d pixels read of %d x %d" % (path, found, w, h))
    return m


def resample(work, width, height):
    """The map stretched to width x height by nearest pixel, each pixel's work kept (a pixel of the
    larger image costs what the pixel it lands in costs): a stand-in for an 8K render's map."""
    h, w = work.shape
    ys = (np.arange(height) * h) // height
    xs = (np.arange(width) * w) // width
    return work[np.ix_(ys, xs)]
