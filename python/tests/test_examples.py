"""The scripts of examples/python run to the end on small settings and write what they say."""
import os
import subprocess
import sys
from pathlib import Path

import pytest

from conftest import data_file

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "python"


def run(script, tmp_path, *args):
    result = subprocess.run([sys.executable, str(EXAMPLES / script), *args], cwd=tmp_path,
                            env=os.environ.copy(), capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    return result.stdout


def test_render_gltf(tmp_path):
    scene = data_file("gltf/cornell_pbr.glb")
    out = run("render_gltf.py", tmp_path, str(scene.parents[1]), "--spp", "2", "-o", "r.png")
    assert "rendered" in out
    try:
        import matplotlib  # noqa: F401  (shown, not saved, when it is installed)
    except ImportError:
        assert (tmp_path / "r.png").read_bytes()[:4] == b"\x89PNG"


def test_spp_sweep(tmp_path):
    scene = data_file("gltf/material_spheres.glb")
    out = run("spp_sweep.py", tmp_path, str(scene.parents[1]), "--max-spp", "4",
              "--size", "24", "16", "-o", "s.png")
    assert out.count("RMSE") == 3 + 3 + 1  # independent and sobol 1, 2, 4; adaptive 4


def test_bunny_rays(tmp_path):
    bunny = data_file("stanford-bunny.obj")
    out = run("bunny_rays.py", tmp_path, str(bunny.parent), "--size", "64", "-o", "d.pfm")
    assert "% hit" in out
    import librt
    depth = librt.read(str(tmp_path / "d.pfm"))
    assert depth.shape == (64, 64, 3) and 0.2 < (depth[:, :, 0] > 0).mean() < 0.9
