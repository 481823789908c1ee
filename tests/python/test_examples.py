"""Each example's script (examples/*/plot.py) loads its run and plots it; what
it prints is physics checked here."""
import os
import re
import subprocess
import sys

import matplotlib.image
import pytest

from conftest import REPO


def plot(name, run, tmp_path):
    png = tmp_path / f"{name}.png"
    r = subprocess.run([sys.executable, os.path.join(REPO, "examples", name, "plot.py"), run, str(png)],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    image = matplotlib.image.imread(png)
    assert image.shape[0] > 300 and image.shape[1] > 300
    assert (image[:, :, :3] < 0.5).mean() > 0.01, "the figure is almost empty"
    return r.stdout


def numbers(text):
    return [float(v) for v in re.findall(r"-?\d+\.\d+", text)]


def test_box_walls_and_floor_carry_the_weight(example_runs, tmp_path):
    out = plot("box", example_runs["box"], tmp_path)
    floor, walls, bound, held = numbers(out.split("the floor carries")[1])[:4]
    # all of the weight: averaged over the last series interval to 0.5 %; in the snapshot to the bed's
    # last sway (the run stops once the kinetic energy is below 5e-11 J/m per grain, when the bed still
    # vibrates at accelerations of ~1 % of g)
    assert held == pytest.approx(1.0, abs=0.005), out
    assert floor + walls == pytest.approx(1.0, abs=0.02), out
    # the walls' share is static friction: within mu times their normal load (its sign is history)
    assert abs(walls) < bound, out


def test_silo_drains(example_runs, tmp_path):
    out = plot("silo", example_runs["silo"], tmp_path)
    m = re.search(r"(\d+) grains above the outlet at t = 0, (\d+) at t = .*discharge (\d+) grains/s", out)
    assert m and int(m[1]) == 200 and int(m[2]) == 0 and int(m[3]) > 50, out


def test_heap_stands_at_an_angle(example_runs, tmp_path):
    out = plot("heap", example_runs["heap"], tmp_path)
    m = re.search(r"(\d+) of 440 grains stay on the base \((\d+) ran off\); angle of repose ([\d.]+) deg", out)
    assert m and int(m[1]) + int(m[2]) == 440 and int(m[1]) > 200, out  # a heap of ~9 layers, not a few grains
    assert 10.0 < float(m[3]) < 25.0, out  # 16.2 deg (14.2 and 19.3 with the grains' seed 4 and 5)


def test_pulloff_drag_falls_as_the_bar_rises(example_runs, tmp_path):
    out = plot("pulloff", example_runs["pulloff"], tmp_path)
    m = re.search(r"largest drag ([\d.]+) N/m at H = ([\d.]+) mm, clear of the bed at H = ([\d.]+) mm", out)
    assert m, out
    drag, at, clear = map(float, m.groups())
    assert drag > 5.0 and at < clear / 3 and 30.0 < clear < 60.0, out  # deepest: most drag; the bed ~43 mm
