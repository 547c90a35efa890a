"""librt.Integrator: an integrator written in Python sees the camera rays librt's own do."""
import numpy as np
import pytest

import librt


def emitter_scene():
    """A sphere of emission 1 and nothing else: the path tracer sees exactly 1 or 0."""
    scene = librt.Scene()
    scene.add_sphere((0, 0, 0), 1.0, scene.add_material("emissive", emission=(1, 1, 1)))
    scene.add_sphere((1.2, 0.6, -1), 0.5, scene.add_material("emissive", emission=(1, 1, 1)))
    return scene


class HitOrMiss(librt.Integrator):
    """1 where the camera ray hits something, 0 where it leaves the scene."""

    def __init__(self):
        self.calls = 0

    def li(self, scene, ray, sampler):
        self.calls += 1
        hit = scene.hit(ray.origin, ray.direction)
        return hit.emission if hit is not None else (0.0, 0.0, 0.0)


def test_python_integrator_matches_the_path_tracer_on_emitters():
    scene = emitter_scene()
    camera = librt.Camera.perspective((0, 0, 4), (0, 0, 0), fov=50, size=(24, 16))
    settings = dict(spp=3, sampler="independent", adaptive=False, seed=5, threads=2)
    integrator = HitOrMiss()
    py = librt.render(scene, camera, integrator=integrator, **settings)
    cpp = librt.render(scene, camera, integrator="path", **settings)
    assert integrator.calls == 24 * 16 * 3  # once per sample
    assert 0.05 < py.mean() < 0.95  # edges jittered: a real mix
    assert np.array_equal(py, cpp)  # the same camera rays, so the same bits


def test_python_integrator_errors_propagate():
    class Broken(librt.Integrator):
        def li(self, scene, ray, sampler):
            raise ZeroDivisionError("in li")

    class NotRgb(librt.Integrator):
        def li(self, scene, ray, sampler):
            return (1.0, 2.0)

    camera = librt.Camera.perspective((0, 0, 4), (0, 0, 0), size=(4, 4))
    with pytest.raises(ZeroDivisionError, match="in li"):
        librt.render(emitter_scene(), camera, spp=1, integrator=Broken())
    with pytest.raises(librt.Error, match="Integrator.li's result"):
        librt.render(emitter_scene(), camera, spp=1, integrator=NotRgb())
    with pytest.raises(librt.Error, match="integrator"):
        librt.render(emitter_scene(), camera, spp=1, integrator=42)
    with pytest.raises(NotImplementedError):
        librt.render(emitter_scene(), camera, spp=1, integrator=librt.Integrator())


def test_sampler_numbers_are_in_the_unit_interval():
    seen = []

    class Draws(librt.Integrator):
        def li(self, scene, ray, sampler):
            u = sampler.next_1d()
            v = sampler.next_2d()
            seen.append((u, *v))
            return (u, v[0], v[1])

    camera = librt.Camera.perspective((0, 0, 4), (0, 0, 0), size=(8, 8))
    img = librt.render(emitter_scene(), camera, spp=4, integrator=Draws())
    draws = np.array(seen)
    assert draws.shape == (256, 3) and (draws >= 0).all() and (draws < 1).all()
    # 256 uniform draws per coordinate: the mean is 0.5 within 5 sigma (sigma = 1/sqrt(12 n)).
    assert np.all(np.abs(draws.mean(axis=0) - 0.5) < 5 / np.sqrt(12 * 256))
    assert img.shape == (8, 8, 3)
