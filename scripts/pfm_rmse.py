#!/usr/bin/env python3
"""RMSE of linear PFM images against a reference.

pfm_rmse.py [--near-above V] REF.pfm IMG.pfm [IMG.pfm ...]

Prints each image's RMSE (also relative to the reference's mean) and MSE. With
--near-above V it also splits the MSE into "near" (the pixels within 2 of one whose
largest reference channel exceeds V: an emitter seen directly and its anti-aliased edge)
and "room" (all others), the split docs/light-targets.md's equal-time tables use.
"""
import argparse
import math
import struct
import sys


def read_pfm(path):
    """(width, height, channels, values) of a PFM file; exits naming the file if it is not one."""
    try:
        with open(path, "rb") as f:
            kind = f.readline().strip()
            if kind not in (b"PF", b"Pf"):
                raise ValueError("not a PFM file (no PF or Pf header)")
            width, height = map(int, f.readline().split())
            scale = float(f.readline())
            if width <= 0 or height <= 0 or scale == 0.0:
                raise ValueError(f"bad size {width} x {height} or scale {scale}")
            channels = 3 if kind == b"PF" else 1
            count = width * height * channels
            order = "<" if scale < 0 else ">"  # negative scale = little-endian
            data = f.read(4 * count)
            if len(data) != 4 * count:
                raise ValueError(f"truncated: {len(data)} of {4 * count} bytes of pixels")
            return width, height, channels, struct.unpack(order + "%df" % count, data)
    except (OSError, ValueError) as e:
        sys.exit(f"{path}: {e}")


def near_mask(width, height, channels, ref, above):
    bright = [max(ref[channels * i:channels * i + channels]) > above for i in range(width * height)]
    near = [False] * (width * height)
    for y in range(height):
        for x in range(width):
            if not bright[y * width + x]:
                continue
            for yy in range(max(0, y - 2), min(height, y + 3)):
                for xx in range(max(0, x - 2), min(width, x + 3)):
                    near[yy * width + xx] = True
    return near


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--near-above", type=float, default=None)
    parser.add_argument("reference")
    parser.add_argument("images", nargs="+")
    args = parser.parse_args()
    width, height, channels, ref = read_pfm(args.reference)
    mean = sum(ref) / len(ref)
    near = None
    if args.near_above is not None:  # 0 is a valid threshold
        near = near_mask(width, height, channels, ref, args.near_above)
    for path in args.images:
        w, h, c, img = read_pfm(path)
        if (w, h, c) != (width, height, channels):
            sys.exit(f"{path}: size differs from the reference")
        pixel_se = [sum((img[c * i + k] - ref[c * i + k]) ** 2 for k in range(c)) / c
                    for i in range(w * h)]
        mse = sum(pixel_se) / len(pixel_se)
        rmse = math.sqrt(mse)
        relative = f"{rmse / mean:.4e}" if mean != 0.0 else "undefined (mean 0)"
        line = f"{path}: RMSE {rmse:.5f}, relative to the mean {relative}, MSE {mse:.4e}"
        if near is not None:
            room = [se for se, n in zip(pixel_se, near) if not n]
            n_near = len(pixel_se) - len(room)
            room_mse = f"{sum(room) / len(room):.4e}" if room else "none (every pixel is near)"
            line += f", room MSE {room_mse} ({n_near} near pixels)"
        print(line)


if __name__ == "__main__":
    main()
