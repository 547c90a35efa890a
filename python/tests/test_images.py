"""librt.write / librt.read / librt.tone_map, and reference counting over many renders."""
import numpy as np
import pytest

import librt


def small_scene():
    scene = librt.Scene()
    scene.add_sphere((0, 0, 0), 1.0, scene.add_material("diffuse", albedo=(0.7, 0.5, 0.3)))
    scene.add_point_light((2, 3, 4), (30, 30, 30))
    scene.add_environment_light(radiance=(0.2, 0.2, 0.2))
    return scene


def test_pfm_and_exr_round_trip_bit_for_bit(tmp_path):
    rng = np.random.default_rng(3)
    image = rng.random((9, 13, 3), dtype=np.float32) * 5
    librt.write(str(tmp_path / "a.pfm"), image)
    assert np.array_equal(librt.read(str(tmp_path / "a.pfm")), image)
    layers = {"albedo": rng.random((9, 13, 3), dtype=np.float32),
              "depth": rng.random((9, 13), dtype=np.float32),
              "sample_count": np.full((9, 13), 4, np.float32)}
    librt.write(str(tmp_path / "a.exr"), image, layers=layers)
    back = librt.read(str(tmp_path / "a.exr"), layers=True)
    assert np.array_equal(back["beauty"], image)
    for k, v in layers.items():
        assert np.array_equal(back[k], v), k


def test_write_refuses_bad_images(tmp_path):
    with pytest.raises(librt.Error, match="not finite"):
        librt.write(str(tmp_path / "nan.pfm"), np.full((2, 2, 3), np.nan, np.float32))
    with pytest.raises(librt.Error, match=r"\(H, W, 3\)"):
        librt.write(str(tmp_path / "bad.pfm"), np.zeros((2, 2, 4), np.float32))
    with pytest.raises(librt.Error, match="nope.xyz"):
        librt.write(str(tmp_path / "nope.xyz"), np.zeros((2, 2, 3), np.float32))
    with pytest.raises(librt.Error, match="missing.pfm"):
        librt.read(str(tmp_path / "missing.pfm"))


def test_tone_map_is_the_reports():
    image = np.array([[[0.0, 0.5, 1.0], [2.0, 0.25, 0.1]]], np.float32)
    out = librt.tone_map(image, exposure=1.0, gamma=0.45)
    expected = np.round(255 * np.clip(image, 0, 1) ** 0.45).astype(np.uint8)
    assert out.dtype == np.uint8 and np.array_equal(out, expected)


def test_png_written(tmp_path):
    img = librt.render(small_scene(), librt.Camera.perspective((0, 0, 5), (0, 0, 0), size=(8, 8)), spp=1)
    librt.write(str(tmp_path / "x.png"), img)
    assert (tmp_path / "x.png").read_bytes()[:4] == b"\x89PNG"


def rss_bytes():
    with open("/proc/self/statm") as f:
        import os
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")


def test_no_leak_over_1000_tiny_renders():
    camera = librt.Camera.perspective((0, 0, 5), (0, 0, 0), size=(64, 64))

    def one():
        scene = small_scene()
        img = librt.render(scene, camera, spp=1, threads=1)
        layers = librt.render(scene, camera, spp=1, threads=1, aovs=True)
        return float(img[32, 32, 0]) + float(layers["depth"][32, 32])

    for _ in range(100):  # warm up: allocator pools, caches
        one()
    before = rss_bytes()
    for _ in range(1000):
        one()
    grown = rss_bytes() - before
    # Each round returns ~50 KiB of image and ~150 KiB of layers: a leak of either would grow
    # the process by 50+ MiB over 1000 rounds.
    assert grown < 16 * 1024 * 1024, f"RSS grew by {grown / 2**20:.1f} MiB"
