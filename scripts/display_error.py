#!/usr/bin/env python3
"""Error of displayed PNG images against a reference PNG made with the same tone curve.

display_error.py REF.png IMG.png [IMG.png ...]

The images are what rt_render writes for a PNG (exposure, tone curve, sRGB encoding); the
reference is best a 16-bit PNG of a long render with the same look (--png-bits 16
--no-denoise), so that its own rounding is negligible. Per image it prints:
  - the RMSE in 8-bit sRGB code values (0-255), the error a viewer's screen shows;
  - relMSE of the display-linear values (sRGB decoded, so after the tone curve):
    mean over pixels and channels of (x - y)^2 / (y^2 + 0.01), Rousselle et al. 2011's
    relative error, which weighs an error by the brightness it sits on as vision does;
  - the share of the squared code-value error in the 1 % worst pixels.
Pure Python (no numpy): reads 8- and 16-bit RGB / RGBA PNGs, non-interlaced.
"""
import argparse
import math
import struct
import sys
import zlib


def read_png(path):
    """(width, height, values in [0, 1] as a flat RGB list) of a PNG; exits naming the file."""
    try:
        with open(path, "rb") as f:
            data = f.read()
        if data[:8] != b"\x89PNG\r\n\x1a\n":
            raise ValueError("not a PNG file (no signature)")
        pos, idat, header = 8, [], None
        while pos + 8 <= len(data):
            length, kind = struct.unpack(">I4s", data[pos:pos + 8])
            body = data[pos + 8:pos + 8 + length]
            if len(body) != length:
                raise ValueError(f"truncated {kind!r} chunk")
            if kind == b"IHDR":
                header = struct.unpack(">IIBBBBB", body)
            elif kind == b"IDAT":
                idat.append(body)
            elif kind == b"IEND":
                break
            pos += 12 + length
        if header is None:
            raise ValueError("no IHDR chunk")
        width, height, depth, colour, _, _, interlace = header
        if colour not in (2, 6) or depth not in (8, 16) or interlace != 0:
            raise ValueError(f"colour type {colour}, depth {depth}, interlace {interlace}: "
                             "only non-interlaced 8/16-bit RGB or RGBA is read")
        channels = 3 if colour == 2 else 4
        step = channels * depth // 8  # bytes per pixel, the filters' distance
        stride = width * step
        raw = zlib.decompress(b"".join(idat))
        if len(raw) != height * (stride + 1):
            raise ValueError(f"{len(raw)} bytes of pixels, expected {height * (stride + 1)}")
        rows, prev = [], bytearray(stride)
        for y in range(height):
            kind = raw[y * (stride + 1)]
            line = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
            for i in range(stride):  # PNG specification, section 9: the five filters
                a = line[i - step] if i >= step else 0
                b = prev[i]
                c = prev[i - step] if i >= step else 0
                if kind == 1:
                    line[i] = (line[i] + a) & 255
                elif kind == 2:
                    line[i] = (line[i] + b) & 255
                elif kind == 3:
                    line[i] = (line[i] + (a + b) // 2) & 255
                elif kind == 4:
                    p = a + b - c
                    pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                    pred = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
                    line[i] = (line[i] + pred) & 255
                elif kind != 0:
                    raise ValueError(f"row {y}: unknown filter {kind}")
            rows.append(line)
            prev = line
        top = float((1 << depth) - 1)
        values = []
        for line in rows:
            if depth == 8:
                samples = line
            else:
                samples = struct.unpack(f">{len(line) // 2}H", bytes(line))
            for x in range(width):
                values.extend(v / top for v in samples[x * channels:x * channels + 3])
        return width, height, values
    except (OSError, ValueError, zlib.error, struct.error) as e:
        sys.exit(f"{path}: {e}")


def srgb_decode(v):
    """IEC 61966-2-1: the display-linear value of an sRGB-encoded one in [0, 1]."""
    return v / 12.92 if v <= 0.04045 else ((v + 0.055) / 1.055) ** 2.4


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("reference")
    parser.add_argument("images", nargs="+")
    args = parser.parse_args()
    width, height, ref = read_png(args.reference)
    ref_linear = [srgb_decode(v) for v in ref]
    for path in args.images:
        w, h, img = read_png(path)
        if (w, h) != (width, height):
            sys.exit(f"{path}: {w} x {h}, the reference is {width} x {height}")
        code_se = [(255.0 * (a - b)) ** 2 for a, b in zip(img, ref)]
        rmse = math.sqrt(sum(code_se) / len(code_se))
        rel = sum((srgb_decode(a) - y) ** 2 / (y * y + 0.01)
                  for a, y in zip(img, ref_linear)) / len(img)
        pixel_se = sorted((sum(code_se[3 * i:3 * i + 3]) for i in range(w * h)), reverse=True)
        worst = max(1, (w * h) // 100)
        total = sum(pixel_se)
        share = sum(pixel_se[:worst]) / total if total > 0.0 else 0.0
        print(f"{path}: RMSE {rmse:.4f} of 255, relMSE {rel:.4e}, "
              f"worst 1 % of pixels {100.0 * share:.1f} % of the squared error")


if __name__ == "__main__":
    main()
