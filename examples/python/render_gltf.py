#!/usr/bin/env python3
"""Renders a glTF file with librt and shows it with matplotlib (or saves a PNG without it).

    python3 render_gltf.py [DATA_DIR] [--scene gltf/cornell_pbr.glb] [--spp 32] [-o out.png]

DATA_DIR defaults to $LIBRT_DATA_DIR. The module must be importable: PYTHONPATH=build/release/python
(see docs/python.md).
"""
import argparse
import os
import time

import librt


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("data_dir", nargs="?", default=os.environ.get("LIBRT_DATA_DIR"))
    parser.add_argument("--scene", default="gltf/cornell_pbr.glb", help="relative to DATA_DIR")
    parser.add_argument("--spp", type=int, default=32)
    parser.add_argument("-o", "--output", default="render_gltf.png")
    args = parser.parse_args()
    if not args.data_dir:
        parser.error("give the data directory or set LIBRT_DATA_DIR")

    scene, camera = librt.load(os.path.join(args.data_dir, args.scene))
    for warning in scene.warnings:
        print("warning:", warning)
    start = time.perf_counter()

    def progress(p):
        print(f"\r{100 * p.fraction:5.1f} %", end="", flush=True)

    layers = librt.render(scene, camera, spp=args.spp, aovs=True, progress=progress)
    print(f"\rrendered {camera.width}x{camera.height} at {args.spp} spp in "
          f"{time.perf_counter() - start:.2f} s")
    image = layers.get("denoised", layers["beauty"])
    display = librt.tone_map(image)  # uint8, the report's gamma 0.45
    try:
        import matplotlib.pyplot as plt
    except ImportError:
        librt.write(args.output, image)
        print(f"matplotlib is not installed: wrote {args.output}")
        return
    fig, axes = plt.subplots(1, 3, figsize=(15, 4))
    axes[0].imshow(display)
    axes[0].set_title("denoised" if "denoised" in layers else "beauty")
    axes[1].imshow((layers["normal"] * 0.5 + 0.5).clip(0, 1))
    axes[1].set_title("normal")
    axes[2].imshow(layers["depth"], cmap="viridis")
    axes[2].set_title("depth")
    for ax in axes:
        ax.axis("off")
    plt.show()


if __name__ == "__main__":
    main()
