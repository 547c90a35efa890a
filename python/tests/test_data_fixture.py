"""data_file: a missing data file skips with its path named, or fails under LIBRT_REQUIRE_DATA=1."""
import os
import subprocess
import sys
from pathlib import Path

TEST = '''
from conftest import data_file

def test_needs_data():
    data_file("no-such-mesh.obj")
'''


def run_pytest(tmp_path, require):
    (tmp_path / "test_needs_data.py").write_text(TEST)
    env = os.environ.copy()
    env["LIBRT_DATA_DIR"] = str(tmp_path / "empty")
    env["LIBRT_REQUIRE_DATA"] = require
    env["PYTHONPATH"] = os.pathsep.join([str(Path(__file__).parent), env.get("PYTHONPATH", "")])
    return subprocess.run([sys.executable, "-m", "pytest", "-q", "-rs", "-p", "no:cacheprovider",
                           str(tmp_path / "test_needs_data.py")], cwd=tmp_path, env=env,
                          capture_output=True, text=True)


def test_missing_data_skips_visibly(tmp_path):
    result = run_pytest(tmp_path, "0")
    assert result.returncode == 0, result.stdout
    assert "1 skipped" in result.stdout and "no-such-mesh.obj not found" in result.stdout


def test_missing_data_fails_in_ci(tmp_path):
    result = run_pytest(tmp_path, "1")
    assert result.returncode != 0
    assert "1 failed" in result.stdout and "LIBRT_REQUIRE_DATA=1" in result.stdout
