#!/usr/bin/env python3
"""Writes a ToyCar-like binary glTF: one body mesh whose whole material emits through an
emission texture that is black but for four lamps, over a ground quad, with a camera.

toycar_like.py OUT.glb [--segments U V] [--floor F] [--strength S] [--no-emission]

Why this shape (issue 42, "emitters as lights"): Khronos' ToyCar gives its body material
an emission texture, so every one of its ~89 k triangles is emissive while only the lamps'
texels are lit. Here: a rounded-box body of 2 U V triangles (default 300 x 150: 90,000)
with uvs (longitude, latitude) into a 512 x 256 sRGB PNG that is black except two white
headlights and two red tail lights (a few texels each); --floor F adds a dither floor
of 8-bit values 0..F over the rest of the texture (0 by default: truly black, as a PNG
emission map usually is; 2 or 3 imitate a compressed map's noise). The emission strength
(KHR_materials_emissive_strength) is S (default 1000); --no-emission leaves the body's
emission out (what the emitters cost is measured against it). No punctual light: rt_render adds
its studio lighting, as it does for ToyCar. Deterministic: a fixed linear congruential
sequence for the dither. Everything is written by this script; nothing of ToyCar's.
"""
import argparse
import json
import math
import struct
import zlib


def png_rgb(width, height, rows):
    """A PNG file (bytes) of 8-bit RGB rows (each a bytes of 3 * width)."""

    def chunk(kind, data):
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body))

    raw = b"".join(b"\x00" + row for row in rows)  # filter 0 on every row
    ihdr = struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", zlib.compress(raw, 9)) +
            chunk(b"IEND", b""))


def emission_texture(width, height, floor):
    """The lamps in uv (u = longitude / 2 pi from the front, +x; v = latitude, 0 at the
    top row as glTF reads it): headlights at u = +-0.035 around 0, tail lights around 0.5,
    all a little above mid height; each 9 x 6 texels."""
    pix = bytearray(3 * width * height)
    state = 12345
    if floor > 0:
        for i in range(width * height):
            state = (1103515245 * state + 12345) % (1 << 31)
            value = (state >> 16) % (floor + 1)
            pix[3 * i:3 * i + 3] = bytes((value, value, value))
    lamps = [(0.035, (255, 255, 235)), (1.0 - 0.035, (255, 255, 235)),
             (0.5 - 0.035, (255, 20, 10)), (0.5 + 0.035, (255, 20, 10))]
    for u, colour in lamps:
        cx, cy = int(u * width), height // 2 - 8  # a little above the equator
        for y in range(cy - 3, cy + 3):
            for x in range(cx - 4, cx + 5):
                i = 3 * (y * width + x % width)
                pix[i:i + 3] = bytes(colour)
    rows = [bytes(pix[3 * width * y:3 * width * (y + 1)]) for y in range(height)]
    return png_rgb(width, height, rows)


def spow(x, e):
    return math.copysign(abs(x) ** e, x)


def body(nu, nv):
    """Positions, normals (of the smooth superellipsoid, numerically), uvs and indices of
    a rounded box 2 m long (x), 0.9 m wide (z), 0.6 m tall, resting 5 cm above y = 0."""
    pos, uv, idx = [], [], []
    a, b, h, e = 1.0, 0.45, 0.3, 0.35
    for j in range(nv + 1):
        phi = -math.pi / 2 + math.pi * j / nv  # latitude, bottom to top
        for i in range(nu + 1):
            theta = 2 * math.pi * i / nu  # longitude from +x toward +z
            c = spow(math.cos(phi), e)
            pos.append((a * c * spow(math.cos(theta), e), 0.35 + h * spow(math.sin(phi), e),
                        b * c * spow(math.sin(theta), e)))
            uv.append((i / nu, 1.0 - j / nv))  # glTF v runs down: the top row is v = 0
    for j in range(nv):
        for i in range(nu):
            p = j * (nu + 1) + i
            q = p + nu + 1
            # Wound so that the normals point outward.
            idx += [p, q, p + 1, p + 1, q, q + 1]
    return pos, uv, idx


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("out")
    ap.add_argument("--segments", nargs=2, type=int, default=[300, 150], metavar=("U", "V"))
    ap.add_argument("--floor", type=int, default=0)
    ap.add_argument("--strength", type=float, default=1000.0)
    ap.add_argument("--no-emission", action="store_true")
    args = ap.parse_args()
    nu, nv = args.segments
    if nu < 8 or nv < 4 or not 0 <= args.floor <= 255 or not args.strength > 0:
        ap.error("need U >= 8, V >= 4, 0 <= F <= 255, S > 0")
    pos, uv, idx = body(nu, nv)
    ground = [(-6.0, 0.0, -6.0), (-6.0, 0.0, 6.0), (6.0, 0.0, 6.0), (6.0, 0.0, -6.0)]
    png = emission_texture(512, 256, args.floor)

    blob = bytearray()
    views, accessors = [], []

    def add(data, target=None):
        while len(blob) % 4:
            blob.append(0)
        views.append({"buffer": 0, "byteOffset": len(blob), "byteLength": len(data)})
        if target:
            views[-1]["target"] = target
        blob.extend(data)
        return len(views) - 1

    def accessor(values, kind, comp):
        flat = [c for v in values for c in (v if isinstance(v, tuple) else (v,))]
        fmt = {5126: "f", 5125: "I"}[comp]
        view = add(struct.pack("<%d%s" % (len(flat), fmt), *flat), 34962 if comp == 5126 else 34963)
        acc = {"bufferView": view, "componentType": comp, "count": len(values), "type": kind}
        if kind == "VEC3":
            acc["min"] = [min(v[k] for v in values) for k in range(3)]
            acc["max"] = [max(v[k] for v in values) for k in range(3)]
        accessors.append(acc)
        return len(accessors) - 1

    body_prim = {"attributes": {"POSITION": accessor(pos, "VEC3", 5126),
                                "TEXCOORD_0": accessor(uv, "VEC2", 5126)},
                 "indices": accessor(idx, "SCALAR", 5125), "material": 0}
    ground_prim = {"attributes": {"POSITION": accessor(ground, "VEC3", 5126)},
                   "indices": accessor([0, 1, 2, 0, 2, 3], "SCALAR", 5125), "material": 1}
    image_view = add(png)
    # Camera at the front left, looking at the car's front and the ground its lamps light.
    eye, target = (3.4, 1.5, 1.8), (0.7, 0.3, 0.0)
    f = [t - e for t, e in zip(target, eye)]
    n = math.sqrt(sum(c * c for c in f))
    f = [c / n for c in f]
    # A rotation whose -z is f (yaw about y, then pitch): a quaternion from yaw and pitch.
    yaw = math.atan2(-f[0], -f[2])
    pitch = math.asin(f[1])
    cy, sy, cp, sp = math.cos(yaw / 2), math.sin(yaw / 2), math.cos(pitch / 2), math.sin(pitch / 2)
    rotation = [cy * sp, sy * cp, -sy * sp, cy * cp]  # q_yaw * q_pitch, (x, y, z, w)
    gltf = {
        "asset": {"version": "2.0", "generator": "librt bench/emitters/toycar_like.py"},
        "extensionsUsed": ["KHR_materials_emissive_strength"],
        "scene": 0,
        "scenes": [{"nodes": [0, 1, 2]}],
        "nodes": [{"mesh": 0, "name": "body"}, {"mesh": 1, "name": "ground"},
                  {"camera": 0, "translation": list(eye), "rotation": rotation}],
        "cameras": [{"type": "perspective",
                     "perspective": {"yfov": 0.6, "znear": 0.01, "aspectRatio": 4 / 3}}],
        "meshes": [{"primitives": [body_prim]}, {"primitives": [ground_prim]}],
        "materials": [
            {"name": "body", "pbrMetallicRoughness": {"baseColorFactor": [0.6, 0.05, 0.04, 1],
                                                      "metallicFactor": 0.0,
                                                      "roughnessFactor": 0.45},
             "emissiveFactor": [1, 1, 1], "emissiveTexture": {"index": 0},
             "extensions": {"KHR_materials_emissive_strength":
                            {"emissiveStrength": args.strength}}},
            {"name": "ground", "pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.5, 0.5, 1],
                                                        "metallicFactor": 0.0,
                                                        "roughnessFactor": 0.8}}],
        "textures": [{"source": 0, "sampler": 0}],
        "samplers": [{"magFilter": 9729, "minFilter": 9729, "wrapS": 10497, "wrapT": 10497}],
        "images": [{"bufferView": image_view, "mimeType": "image/png"}],
        "accessors": accessors,
        "bufferViews": views,
        "buffers": [{"byteLength": len(blob)}],
    }
    if args.no_emission:
        for key in ("emissiveFactor", "emissiveTexture", "extensions"):
            del gltf["materials"][0][key]
        del gltf["extensionsUsed"]
    text = json.dumps(gltf, separators=(",", ":")).encode()
    text += b" " * (-len(text) % 4)
    blob.extend(b"\x00" * (-len(blob) % 4))
    out = struct.pack("<III", 0x46546C67, 2, 12 + 8 + len(text) + 8 + len(blob))
    out += struct.pack("<II", len(text), 0x4E4F534A) + text
    out += struct.pack("<II", len(blob), 0x004E4942) + bytes(blob)
    with open(args.out, "wb") as fh:
        fh.write(out)


if __name__ == "__main__":
    main()
