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
