"""librt.load and librt.render against rt_render, errors, progress and cancellation."""
import os
import signal
import subprocess
import sys
import textwrap

import numpy as np
import pytest

import librt
from conftest import write_gltf


def rt_render():
    path = os.environ.get("LIBRT_RT_RENDER")
    if not path:
        pytest.skip("LIBRT_RT_RENDER (the rt_render executable) not set: run through ctest")
    return path


def test_version_is_the_project_version():
    assert librt.__version__ == os.environ.get("LIBRT_VERSION", librt.__version__)
    assert librt.__version__.count(".") == 2


@pytest.mark.parametrize("sampler,adaptive", [("sobol", True), ("independent", False)])
def test_render_is_bit_identical_to_rt_render(tmp_path, sampler, adaptive):
    scene_path = write_gltf(tmp_path)
    out = tmp_path / "cpp.pfm"
    args = [rt_render(), str(scene_path), "-o", str(out), "--spp", "8", "--size", "48x32",
            "--seed", "7", "--threads", "3", "--sampler", sampler, "--no-denoise", "-q"]
    args.append("--adaptive" if adaptive else "--no-adaptive")
    subprocess.run(args, check=True)
    cpp = librt.read(str(out))
    scene, camera = librt.load(str(scene_path), size=(48, 32))
    assert scene.warnings == [] and scene.lighting_note == ""  # the file's own lights
    py = librt.render(scene, camera, spp=8, seed=7, threads=2, sampler=sampler, adaptive=adaptive)
    assert py.shape == (32, 48, 3) and py.dtype == np.float32
    assert py.mean() > 0.0  # lit: a black image would match trivially
    assert np.array_equal(py, cpp)


@pytest.mark.parametrize("adaptive", [True, False])
def test_region_is_the_full_renders_pixels(tmp_path, adaptive):
    scene, camera = librt.load(str(write_gltf(tmp_path)), size=(48, 32))
    full = librt.render(scene, camera, spp=8, seed=5, threads=2, adaptive=adaptive)
    part = librt.render(scene, camera, spp=8, seed=5, threads=2, adaptive=adaptive,
                        region=(11, 6, 20, 15))
    assert part.shape == (15, 20, 3) and part.mean() > 0
    assert np.array_equal(part, full[6:21, 11:31])
    layers = librt.render(scene, camera, spp=8, seed=5, adaptive=adaptive, aovs=True,
                          region=(11, 6, 20, 15))
    assert all(v.shape[:2] == (15, 20) for v in layers.values())
    assert np.array_equal(layers["beauty"], part)


def test_region_matches_rt_render(tmp_path):
    scene_path = write_gltf(tmp_path)
    out = tmp_path / "cpp.pfm"
    subprocess.run([rt_render(), str(scene_path), "-o", str(out), "--spp", "4", "--size", "48x32",
                    "--seed", "3", "--threads", "2", "--region", "5,4,30,20", "--no-denoise", "-q"],
                   check=True)
    scene, camera = librt.load(str(scene_path), size=(48, 32))
    py = librt.render(scene, camera, spp=4, seed=3, threads=2, region=(5, 4, 30, 20))
    assert np.array_equal(py, librt.read(str(out)))


def test_bad_regions_are_refused(tmp_path):
    scene, camera = librt.load(str(write_gltf(tmp_path)), size=(48, 32))
    for region in [(0, 0, 0, 4), (-1, 0, 4, 4), (0, 0, 4), "0,0,4,4", (0.5, 0, 4, 4)]:
        with pytest.raises(librt.Error, match=r"region: .* must be \(x, y, width, height\)"):
            librt.render(scene, camera, spp=1, region=region)
    with pytest.raises(librt.Error, match="region"):  # beyond the 48 x 32 image
        librt.render(scene, camera, spp=1, region=(40, 0, 9, 4))
    with pytest.raises(librt.Error, match="splats"):  # light paths land on any pixel
        librt.render(scene, camera, spp=1, integrator="bdpt", region=(0, 0, 8, 8))


def emitter_scene(scene):
    """A bright emissive quad and one 1000 times dimmer (a 'negligible' emitter), two triangles
    each."""
    quad = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], np.float32)
    tris = np.array([[0, 1, 2], [0, 2, 3]], np.uint32)
    scene.add_mesh(quad, tris, scene.add_material("emissive", emission=(10, 10, 10)))
    scene.add_mesh(quad + np.float32([3, 0, 0]), tris,
                   scene.add_material("emissive", emission=(0.01, 0.01, 0.01)))
    return scene


def test_all_emitters_lights_every_emissive_triangle(tmp_path):
    default = emitter_scene(librt.Scene())
    default.commit()
    every = emitter_scene(librt.Scene())
    every.set_triangle_light_settings(negligible_power=0, negligible_radiance=0)
    every.commit()
    assert default.light_count == 2 and every.light_count == 4
    assert every.triangle_light_settings == {"negligible_power": 0, "negligible_radiance": 0}
    assert default.triangle_light_settings["negligible_power"] == pytest.approx(0.01)
    with pytest.raises(librt.Error, match="negligible_power"):
        every.set_triangle_light_settings(negligible_power=2)
    scene, _ = librt.load(str(write_gltf(tmp_path)), all_emitters=True)
    assert scene.triangle_light_settings == {"negligible_power": 0, "negligible_radiance": 0}


def test_render_returns_a_view_owning_the_film(tmp_path):
    scene, camera = librt.load(str(write_gltf(tmp_path)), size=(16, 8))
    img = librt.render(scene, camera, spp=1)
    assert not img.flags["OWNDATA"] and img.base is not None  # no copy: a capsule owns it
    assert img.flags["C_CONTIGUOUS"] and img.strides == (16 * 12, 12, 4)


def test_aovs_hold_every_layer(tmp_path):
    scene, camera = librt.load(str(write_gltf(tmp_path)), size=(24, 16))
    plain = librt.render(scene, camera, spp=4, seed=1)
    layers = librt.render(scene, camera, spp=4, seed=1, aovs=True)
    assert set(layers) == {"beauty", "albedo", "normal", "depth", "sample_count", "denoised"}
    assert np.array_equal(layers["beauty"], plain)  # the same samples, the same bits
    assert layers["depth"].shape == (16, 24) and layers["sample_count"].shape == (16, 24)
    assert abs(layers["sample_count"].mean() - 4.0) < 1e-3  # adaptive: 4 on average
    # A pixel's normal is the mean of its samples' unit normals: unit inside a surface,
    # shorter where the pixel straddles an edge, 0 where every sample missed.
    norms = np.linalg.norm(layers["normal"], axis=2)
    assert np.all(norms <= 1 + 1e-5) and (np.abs(norms - 1) < 1e-5).mean() > 0.2
    assert np.isinf(layers["depth"][norms == 0]).all()


def test_errors_name_the_file_and_json_path(tmp_path):
    bad = write_gltf(tmp_path, "bad.gltf", material_index=3)
    with pytest.raises(librt.Error) as e:
        librt.load(str(bad))
    assert "bad.gltf" in str(e.value)
    assert "meshes[0].primitives[0].material" in str(e.value)
    with pytest.raises(librt.Error, match="missing.glb"):
        librt.load(str(tmp_path / "missing.glb"))
    scene, camera = librt.load(str(write_gltf(tmp_path)))
    with pytest.raises(librt.Error, match="samples_per_pixel"):
        librt.render(scene, camera, spp=0)
    with pytest.raises(librt.Error, match="sampler"):
        librt.render(scene, camera, sampler="halton")
    camera.fov = 200.0
    with pytest.raises(librt.Error, match="vertical_fov"):
        librt.render(scene, camera)
    assert issubclass(librt.Error, RuntimeError)


def big_render_args(tmp_path):
    scene, camera = librt.load(str(write_gltf(tmp_path)), size=(256, 256))
    # 2^20 samples per pixel: hours of work, so only the cancellation can end it.
    return scene, camera, 1 << 20


def test_progress_callback_returning_false_cancels(tmp_path):
    scene, camera, spp = big_render_args(tmp_path)
    seen = []

    def progress(p):
        seen.append(p.fraction)
        return False

    with pytest.raises(librt.Cancelled):
        librt.render(scene, camera, spp=spp, threads=2, progress=progress)
    assert len(seen) == 1 and seen[0] < 1.0  # stopped at the first report, part way
    assert issubclass(librt.Cancelled, librt.Error)


def test_progress_callback_exception_propagates(tmp_path):
    scene, camera, spp = big_render_args(tmp_path)

    def progress(p):
        raise ValueError("stop here")

    with pytest.raises(ValueError, match="stop here"):
        librt.render(scene, camera, spp=spp, threads=2, progress=progress)


def test_progress_callback_that_returns_none_lets_the_render_finish(tmp_path):
    scene, camera = librt.load(str(write_gltf(tmp_path)), size=(16, 16))
    seen = []
    img = librt.render(scene, camera, spp=4, progress=lambda p: seen.append(p.fraction))
    assert seen and seen[-1] == 1.0 and img.shape == (16, 16, 3)


def test_ctrl_c_cancels_with_keyboard_interrupt(tmp_path):
    scene_path = write_gltf(tmp_path)
    # The child installs Python's own SIGINT handler: a process started in the background
    # by a non-interactive shell inherits SIGINT ignored, and Python then keeps it ignored.
    script = textwrap.dedent(f"""
        import signal, sys, librt
        signal.signal(signal.SIGINT, signal.default_int_handler)
        scene, camera = librt.load({str(scene_path)!r}, size=(256, 256))
        told = []
        def progress(p):
            if not told:
                print("rendering", flush=True)
                told.append(1)
        try:
            librt.render(scene, camera, spp=1 << 20, threads=2, progress=progress)
            print("finished")
        except KeyboardInterrupt:
            print("interrupted")
    """)
    child = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE, text=True,
                             env=os.environ.copy())
    assert child.stdout.readline().strip() == "rendering"
    child.send_signal(signal.SIGINT)
    try:
        rest, _ = child.communicate(timeout=600)  # a guard against a hang, not a measurement
    except subprocess.TimeoutExpired:
        child.kill()
        child.communicate()
        pytest.fail("SIGINT did not stop the render")
    assert rest.strip() == "interrupted" and child.returncode == 0
