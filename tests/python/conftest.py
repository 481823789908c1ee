"""The examples' runs, made once per test session with the dem2d of DEM2D_BIN
(ctest passes the build's; default build/release/sim/dem2d)."""
import os
import subprocess
import sys

import pytest

REPO = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
sys.path.insert(0, os.path.join(REPO, "python"))


def dem2d_bin():
    return os.environ.get("DEM2D_BIN", os.path.join(REPO, "build", "release", "sim", "dem2d"))


def run_scene(scene, out, *extra):
    cmd = [dem2d_bin(), "run", os.path.join(REPO, "examples", scene), "--out", str(out), "--threads", "1",
           "--progress", "0", *extra]
    r = subprocess.run(cmd, capture_output=True, text=True)
    assert r.returncode == 0, f"{' '.join(cmd)}: exit {r.returncode}\n{r.stderr}"
    return os.path.join(str(out), "run.h5")


@pytest.fixture(scope="session")
def example_runs(tmp_path_factory):
    """run.h5 of each example: box, silo, heap, pulloff (from its own fill)."""
    d = tmp_path_factory.mktemp("examples")
    runs = {name: run_scene(f"{name}/scene.toml", d / name) for name in ("box", "silo", "heap")}
    fill = run_scene("pulloff/fill.toml", d / "pulloff_fill")
    runs["pulloff"] = run_scene("pulloff/pulloff.toml", d / "pulloff", "--initial", fill)
    return runs
