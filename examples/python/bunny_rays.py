#!/usr/bin/env python3
"""Rays cast from NumPy at the Stanford bunny: a depth image and the throughput.

    python3 bunny_rays.py [DATA_DIR] [-o bunny_depth.pfm]

Reads DATA_DIR/stanford-bunny.obj (DATA_DIR defaults to $LIBRT_DATA_DIR), builds the mesh
from arrays, shoots one orthographic ray per pixel with scene.intersect (all threads, the GIL
released) and writes the hit distance as an image.
"""
import argparse
import os
import time

import numpy as np

import librt


def read_obj(path):
    """Positions and triangles of a triangulated OBJ (v and f lines only)."""
    vertices, faces = [], []
    with open(path) as f:
        for line in f:
            if line.startswith("v "):
                vertices.append(line.split()[1:4])
            elif line.startswith("f "):
                faces.append([int(x.split("/")[0]) - 1 for x in line.split()[1:4]])
    return np.asarray(vertices, np.float32), np.asarray(faces, np.uint32)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("data_dir", nargs="?", default=os.environ.get("LIBRT_DATA_DIR"))
    parser.add_argument("--size", type=int, default=512)
    parser.add_argument("-o", "--output", default="bunny_depth.pfm")
    args = parser.parse_args()
    if not args.data_dir:
        parser.error("give the data directory or set LIBRT_DATA_DIR")
    vertices, indices = read_obj(os.path.join(args.data_dir, "stanford-bunny.obj"))
    scene = librt.Scene()
    scene.add_mesh(vertices, indices, scene.add_material("diffuse"))
    scene.commit()
    lo, hi = vertices.min(axis=0), vertices.max(axis=0)
    n = args.size
    # A grid of rays along -z over the bunny's box, top row first as images are.
    xs = np.linspace(lo[0], hi[0], n, dtype=np.float32)
    ys = np.linspace(hi[1], lo[1], n, dtype=np.float32)
    x, y = np.meshgrid(xs, ys)
    origins = np.stack([x.ravel(), y.ravel(), np.full(x.size, hi[2] + 1, np.float32)], axis=1)
    directions = np.tile(np.array([0, 0, -1], np.float32), (x.size, 1))
    start = time.perf_counter()
    hits = scene.intersect(origins, directions)
    seconds = time.perf_counter() - start
    hit = np.isfinite(hits["t"])
    print(f"{x.size} rays in {seconds * 1e3:.1f} ms ({x.size / seconds / 1e6:.1f} M rays/s), "
          f"{hit.mean() * 100:.1f} % hit, {len(np.unique(hits['primitive_id'][hit]))} "
          f"of {len(indices)} triangles seen")
    depth = np.where(hit, hits["t"], 0).reshape(n, n)
    librt.write(args.output, np.repeat(depth[:, :, None], 3, axis=2).astype(np.float32))
    print("wrote", args.output)


if __name__ == "__main__":
    main()
