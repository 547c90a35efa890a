#!/usr/bin/env python3
"""RMSE against render time for librt's samplers: a sweep of samples per pixel.

    python3 spp_sweep.py [DATA_DIR] [--scene gltf/material_spheres.glb] [-o spp_sweep.png]

Each sampler (independent, Sobol', each with and without adaptive sampling) renders the scene
at 1, 2, 4, ... 64 spp; the error is against a 1024 spp Sobol' reference. Plots log RMSE over
log seconds with matplotlib, or prints the table when it is not installed.
"""
import argparse
import os
import time

import numpy as np

import librt


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("data_dir", nargs="?", default=os.environ.get("LIBRT_DATA_DIR"))
    parser.add_argument("--scene", default="gltf/material_spheres.glb")
    parser.add_argument("--size", type=int, nargs=2, default=(160, 120))
    parser.add_argument("--max-spp", type=int, default=64)
    parser.add_argument("-o", "--output", default="spp_sweep.png")
    args = parser.parse_args()
    if not args.data_dir:
        parser.error("give the data directory or set LIBRT_DATA_DIR")
    scene, camera = librt.load(os.path.join(args.data_dir, args.scene), size=tuple(args.size))
    reference = librt.render(scene, camera, spp=16 * args.max_spp, seed=1000)
    results = {}
    for sampler, adaptive in [("independent", False), ("sobol", False), ("sobol", True)]:
        label = sampler + (" adaptive" if adaptive else "")
        rows = []
        spp = 1 if not adaptive else 4  # adaptive sampling needs a pilot of several samples
        while spp <= args.max_spp:
            start = time.perf_counter()
            image = librt.render(scene, camera, spp=spp, sampler=sampler, adaptive=adaptive)
            seconds = time.perf_counter() - start
            rmse = float(np.sqrt(np.mean((image - reference) ** 2)))
            rows.append((spp, seconds, rmse))
            print(f"{label:20s} {spp:5d} spp {seconds:8.3f} s  RMSE {rmse:.5f}")
            spp *= 2
        results[label] = rows
    try:
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib is not installed: the table above is the result")
        return
    for label, rows in results.items():
        plt.loglog([r[1] for r in rows], [r[2] for r in rows], "o-", label=label)
    plt.xlabel("render time (s)")
    plt.ylabel("RMSE against the reference")
    plt.legend()
    plt.savefig(args.output, dpi=120)
    print("wrote", args.output)


if __name__ == "__main__":
    main()
