#!/usr/bin/env python3
"""scene.intersect's throughput on the bunny, to compare with librt_bench's C++ rays.

    PYTHONPATH=build/release/python python3 bench/python/intersect_throughput.py [DATA_DIR]
    ./build/release/bench/librt_bench --benchmark_filter='bunny/librt/incoherent/1t'

With --same-rays, the rays and mesh come from rays.bin and mesh.bin in the current directory,
as `build/release/bench/librt_query_layers dump` writes them: then the C++ layers
(`librt_query_layers bvh|top|scene`) and this script trace exactly the same rays.

The rays are librt_bench's "incoherent" set drawn with NumPy: the bunny centred and scaled to
a diagonal of 100 (as bench/bvh_bench.cpp does), origins uniform on a sphere of 1.5 times
its half-diagonal, directions toward uniform points of its box (tests/ray_sets.h). One
thread, 1M rays, Mrays per CPU second (time.process_time around the call: the arrays in and
out included, the GIL released), the median of 5 runs; once with new output arrays each
call, once writing into the same arrays through out=.
"""
import os
import statistics
import sys
import time

import numpy as np

import librt


def read_obj(path):
    vertices, faces = [], []
    with open(path) as f:
        for line in f:
            if line.startswith("v "):
                vertices.append(line.split()[1:4])
            elif line.startswith("f "):
                faces.append([int(x.split("/")[0]) - 1 for x in line.split()[1:4]])
    return np.asarray(vertices, np.float32), np.asarray(faces, np.uint32)


def same_rays():
    nv, nt = (int(x) for x in np.fromfile("mesh.bin", np.uint32, 2))
    vertices = np.fromfile("mesh.bin", np.float32, nv * 3, offset=8).reshape(nv, 3)
    indices = np.fromfile("mesh.bin", np.uint32, nt * 3, offset=8 + 12 * nv).reshape(nt, 3)
    rays = np.fromfile("rays.bin", np.float32).reshape(-1, 6)
    return vertices, indices, np.ascontiguousarray(rays[:, :3]), np.ascontiguousarray(rays[:, 3:])


def main():
    args = [a for a in sys.argv[1:] if a != "--same-rays"]
    if len(args) < len(sys.argv) - 1:
        vertices, indices, origins, directions = same_rays()
        scene = librt.Scene()
        scene.add_mesh(vertices, indices, scene.add_material("diffuse"))
        scene.commit()
        measure(scene, origins, directions)
        return
    data = args[0] if args else os.environ.get("LIBRT_DATA_DIR", "../shared/data")
    vertices, indices = read_obj(os.path.join(data, "stanford-bunny.obj"))
    lo, hi = vertices.min(axis=0), vertices.max(axis=0)
    vertices = ((vertices - (lo + hi) / 2) * (100 / np.linalg.norm(hi - lo))).astype(np.float32)
    scene = librt.Scene()
    scene.add_mesh(vertices, indices, scene.add_material("diffuse"))
    scene.commit()
    lo, hi = vertices.min(axis=0), vertices.max(axis=0)
    n = 1_000_000
    rng = np.random.default_rng(42)
    z = 1 - 2 * rng.random(n)
    s = np.sqrt(np.maximum(0, 1 - z * z))
    phi = 2 * np.pi * rng.random(n)
    radius = 1.5 * 0.5 * np.linalg.norm(hi - lo)
    origins = ((lo + hi) / 2 + radius * np.stack([s * np.cos(phi), s * np.sin(phi), z], 1)).astype(np.float32)
    targets = lo + (hi - lo) * rng.random((n, 3))
    d = targets - origins
    directions = (d / np.linalg.norm(d, axis=1, keepdims=True)).astype(np.float32)
    measure(scene, origins, directions)


def measure(scene, origins, directions):
    n = len(origins)
    # New arrays every call, then the same arrays reused through out= (no allocation).
    out = scene.intersect(origins, directions, threads=1)
    for label, kwargs in (("new arrays", {}), ("out= reused", {"out": out})):
        rates = []
        for _ in range(5):
            start = time.process_time()
            hits = scene.intersect(origins, directions, threads=1, **kwargs)
            rates.append(n / (time.process_time() - start) / 1e6)
        print(f"scene.intersect ({label}), 1 thread: {statistics.median(rates):.2f} Mrays/CPU s "
              f"(runs {', '.join(f'{r:.2f}' for r in rates)}), {np.isfinite(hits['t']).mean():.1%} hit")


if __name__ == "__main__":
    main()
