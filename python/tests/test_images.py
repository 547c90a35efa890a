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


def test_tone_curves_are_rt_renders():
    grey = np.full((1, 1, 3), 0.18, np.float32)
    srgb_grey = round(255 * (1.055 * 0.18 ** (1 / 2.4) - 0.055))
    for curve in ["clamp", "aces", "agx"]:  # each shows mid grey as clamp does
        assert abs(int(librt.tone_map(grey, curve=curve)[0, 0, 0]) - srgb_grey) <= 1, curve
    # AgX: white from 6.5 stops above mid grey, black from 10 below; clamp clips at 1 already.
    values = np.array([[[0.18 * 2 ** -10.5] * 3, [0.18 * 2 ** 3] * 3, [0.18 * 2 ** 6.6] * 3]], np.float32)
    agx = librt.tone_map(values, curve="agx")
    assert agx[0, 0].max() == 0 and 0 < agx[0, 1].min() < 255 and agx[0, 2].min() == 255
    assert librt.tone_map(values, curve="clamp")[0, 1].min() == 255
    ramp = np.geomspace(1e-3, 50, 64, dtype=np.float32)[None, :, None].repeat(3, axis=2)
    assert np.all(np.diff(librt.tone_map(ramp, curve="agx")[0, :, 0].astype(int)) >= 0)
    # Exposure multiplies before the curve.
    assert np.array_equal(librt.tone_map(values, exposure=4.0, curve="agx"),
                          librt.tone_map(values * 4, curve="agx"))
    with pytest.raises(librt.Error, match="curve: 'filmic' is none of clamp, aces, agx"):
        librt.tone_map(grey, curve="filmic")
    with pytest.raises(librt.Error, match="gamma"):
        librt.tone_map(grey, gamma=0.5, curve="agx")


def test_agx_png_is_rt_renders(tmp_path):
    import os
    import subprocess
    from conftest import write_gltf
    rt_render = os.environ.get("LIBRT_RT_RENDER")
    if not rt_render:
        pytest.skip("LIBRT_RT_RENDER (the rt_render executable) not set: run through ctest")
    scene_path = write_gltf(tmp_path)
    subprocess.run([rt_render, str(scene_path), "-o", str(tmp_path / "cpp.png"), "--spp", "4",
                    "--size", "48x32", "--seed", "2", "--threads", "2", "--tonemap", "agx",
                    "--exposure", "1", "--no-denoise", "-q"], check=True)
    scene, camera = librt.load(str(scene_path), size=(48, 32))
    image = librt.render(scene, camera, spp=4, seed=2, threads=2)
    librt.write(str(tmp_path / "py.png"), image, exposure=2.0, curve="agx")
    assert (tmp_path / "py.png").read_bytes() == (tmp_path / "cpp.png").read_bytes()
    with pytest.raises(librt.Error, match="curve applies to .png only"):
        librt.write(str(tmp_path / "py.pfm"), image, curve="agx")


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
