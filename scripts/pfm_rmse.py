#!/usr/bin/env python3
"""RMSE of linear PFM images against a reference: pfm_rmse.py REF.pfm IMG.pfm [IMG.pfm ...]"""
import math
import struct
import sys


def read_pfm(path):
    with open(path, "rb") as f:
        kind = f.readline().strip()
        width, height = map(int, f.readline().split())
        scale = float(f.readline())
        count = width * height * (3 if kind == b"PF" else 1)
        order = "<" if scale < 0 else ">"  # negative scale = little-endian
        return struct.unpack(order + "%df" % count, f.read(4 * count))


ref = read_pfm(sys.argv[1])
mean = sum(ref) / len(ref)
for path in sys.argv[2:]:
    img = read_pfm(path)
    if len(img) != len(ref):
        sys.exit(f"{path}: size differs from the reference")
    rmse = math.sqrt(sum((a - b) ** 2 for a, b in zip(img, ref)) / len(ref))
    print(f"{path}: RMSE {rmse:.5f}, relative to the mean {rmse / mean:.4f}")
