"""Shared fixtures of the librt Python tests (run by ctest as python.pytest; docs/python.md).

Data files come from $LIBRT_DATA_DIR (ctest passes the build's LIBRT_DATA_DIR). A missing
file skips its test with a message, or fails it when LIBRT_REQUIRE_DATA=1 (CI), as the C++
tests do (tests/test_support.h).
"""
import json
import os
import struct
from pathlib import Path

import numpy as np
import pytest


def data_file(name):
    """The path of a data file, or a visible skip (a failure under LIBRT_REQUIRE_DATA=1)."""
    # $LIBRT_DATA_DIR, else the build's LIBRT_DATA_DIR (ctest sets LIBRT_DEFAULT_DATA_DIR), else
    # ../shared/data beside the source tree.
    default = Path(__file__).resolve().parents[2] / ".." / "shared" / "data"
    root = Path(os.environ.get("LIBRT_DATA_DIR") or os.environ.get("LIBRT_DEFAULT_DATA_DIR") or default)
    path = root / name
    if not path.is_file():
        message = f"data file {path} not found (set LIBRT_DATA_DIR)"
        if os.environ.get("LIBRT_REQUIRE_DATA") == "1":
            pytest.fail(message + "; LIBRT_REQUIRE_DATA=1 makes this an error")
        pytest.skip(message)
    return path


def read_obj(path):
    """Positions (N, 3) float32 and triangles (M, 3) uint32 of a triangulated OBJ (v and f lines)."""
    vertices, faces = [], []
    with open(path) as f:
        for line in f:
            if line.startswith("v "):
                vertices.append([float(x) for x in line.split()[1:4]])
            elif line.startswith("f "):
                faces.append([int(x.split("/")[0]) - 1 for x in line.split()[1:4]])
    return np.asarray(vertices, np.float32), np.asarray(faces, np.uint32)


def write_gltf(directory, name="scene.gltf", material_index=0):
    """A small glTF written here: a floor quad and a tilted triangle, a point light and a spot
    light (KHR_lights_punctual), a perspective camera. material_index != 0 makes it invalid."""
    positions = np.array([[-2, 0, -2], [2, 0, -2], [2, 0, 2], [-2, 0, 2],
                          [-0.5, 0, 0], [0.5, 0, 0], [0, 1, -0.3]], np.float32)
    indices = np.array([0, 2, 1, 0, 3, 2, 4, 5, 6], np.uint16)
    blob = positions.tobytes() + indices.tobytes()
    (Path(directory) / "scene.bin").write_bytes(blob)
    doc = {
        "asset": {"version": "2.0"},
        "extensionsUsed": ["KHR_lights_punctual"],
        "extensions": {"KHR_lights_punctual": {"lights": [
            {"type": "point", "color": [1, 0.9, 0.8], "intensity": 40},
            {"type": "spot", "color": [0.3, 0.5, 1], "intensity": 60,
             "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.6}}]}},
        "scene": 0,
        "scenes": [{"nodes": [0, 1, 2, 3]}],
        "nodes": [
            {"mesh": 0},
            {"camera": 0, "translation": [0, 1.2, 4], "rotation": [-0.1305262, 0, 0, 0.9914449]},
            {"extensions": {"KHR_lights_punctual": {"light": 0}}, "translation": [1, 2.5, 1]},
            {"extensions": {"KHR_lights_punctual": {"light": 1}}, "translation": [-1, 3, 0],
             "rotation": [-0.7071068, 0, 0, 0.7071068]}],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.7, "aspectRatio": 1.5,
                                                              "znear": 0.01}}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1,
                                    "material": material_index}]}],
        "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.6, 0.4, 1],
                                                "metallicFactor": 0.0, "roughnessFactor": 0.6}}],
        "buffers": [{"uri": "scene.bin", "byteLength": len(blob)}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": positions.nbytes},
                        {"buffer": 0, "byteOffset": positions.nbytes, "byteLength": indices.nbytes}],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 7, "type": "VEC3",
             "min": [-2, 0, -2], "max": [2, 1, 2]},
            {"bufferView": 1, "componentType": 5123, "count": 9, "type": "SCALAR"}],
    }
    path = Path(directory) / name
    path.write_text(json.dumps(doc))
    return path
