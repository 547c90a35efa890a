#!/usr/bin/env python3
"""Writes a copy of a binary glTF (.glb) with some materials changed, for experiments.

glb_variant.py IN.glb OUT.glb EDIT [EDIT ...]

Each EDIT is NAME.one-sided (doubleSided false: an emitter then emits from its front
only), NAME.dielectric (metallicFactor 0), NAME.opaque (KHR_materials_transmission
removed) or NAME.rough (roughnessFactor 1), NAME a material's name; or NODE.raise (the
node named NODE moved 2 mm up, +y: off a surface it rests on).
docs/materials-and-lights.md uses it to measure which of cornell_pbr.glb's surfaces
limit its emissive-panel target. The binary chunk is copied unchanged; only the JSON
chunk is rewritten.
"""
import json
import struct
import sys

JSON_CHUNK = 0x4E4F534A


def main():
    if len(sys.argv) < 4:
        sys.exit(__doc__)
    source, target, edits = sys.argv[1], sys.argv[2], sys.argv[3:]
    try:
        with open(source, "rb") as f:
            data = f.read()
    except OSError as e:
        sys.exit(f"{source}: {e}")
    if len(data) < 20 or data[:4] != b"glTF" or struct.unpack("<I", data[4:8])[0] != 2:
        sys.exit(f"{source}: not a version 2 binary glTF")
    length, kind = struct.unpack("<II", data[12:20])
    if kind != JSON_CHUNK or 20 + length > len(data):
        sys.exit(f"{source}: the first chunk is not a whole JSON chunk")
    try:
        gltf = json.loads(data[20:20 + length])
    except ValueError as e:
        sys.exit(f"{source}: JSON chunk: {e}")
    rest = data[20 + length:]
    materials = {m.get("name"): m for m in gltf.get("materials", [])}
    nodes = {n.get("name"): n for n in gltf.get("nodes", [])}
    for edit in edits:
        name, dot, what = edit.rpartition(".")
        if not dot:
            sys.exit(f"{edit}: an edit is NAME.one-sided, NAME.dielectric, NAME.opaque, "
                     "NAME.rough or NODE.raise")
        if what == "raise":
            if name not in nodes:
                sys.exit(f"{edit}: {source} has no node named '{name}'")
            node = nodes[name]
            if "matrix" in node:
                sys.exit(f"{edit}: node '{name}' is placed by a matrix; only a translation is moved")
            t = node.setdefault("translation", [0, 0, 0])
            t[1] += 0.002
            continue
        if name not in materials:
            sys.exit(f"{edit}: {source} has no material named '{name}'")
        m = materials[name]
        if what == "one-sided":
            m["doubleSided"] = False
        elif what == "dielectric":
            m.setdefault("pbrMetallicRoughness", {})["metallicFactor"] = 0
        elif what == "opaque":
            extensions = m.get("extensions", {})
            extensions.pop("KHR_materials_transmission", None)
            if not extensions:
                m.pop("extensions", None)
        elif what == "rough":
            m.setdefault("pbrMetallicRoughness", {})["roughnessFactor"] = 1
        else:
            sys.exit(f"{edit}: the edit must be one-sided, dielectric, opaque, rough or raise")
    text = json.dumps(gltf, separators=(",", ":")).encode()
    text += b" " * (-len(text) % 4)  # chunks are 4-byte aligned; JSON pads with spaces
    body = struct.pack("<II", len(text), JSON_CHUNK) + text + rest
    with open(target, "wb") as f:
        f.write(struct.pack("<4sII", b"glTF", 2, 12 + len(body)) + body)


if __name__ == "__main__":
    main()
