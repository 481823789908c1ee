"""Both readers (the Python one and `dem2d inspect`, the analyses') on the /parameters of bodies that move
by a schedule and turn about a pivot: every damage refused by both, naming the file and the value (they
disagreed: the Python reader took an unknown motion kind and a missing period, the C++ one cast a count
of 1e300 cycles to an int)."""
import os
import re
import subprocess

import h5py
import numpy as np
import pytest

import dem2d
from conftest import REPO, dem2d_bin

# valid_minimal's four disks, a paddle shaken by a sine schedule repeated twice and a bar turned about a pivot
BODIES = """
[[body]]
name = "paddle"
a = [-0.015, 0.04]
b = [-0.005, 0.04]
thickness = 1e-3
motion = [{ kind = "sine", amplitude = [1e-3, 0.0], period = 0.01, cycles = 2 }]
motion_repeat = 2

[[body]]
name = "turner"
a = [0.005, 0.03]
b = [0.015, 0.03]
thickness = 1e-3
pivot = [0.01, 0.03]
motion = [{ kind = "hold", duration = 0.01 }, { kind = "ramp", angular_velocity = 2.0, duration = 0.01 },
          { kind = "constant", angular_velocity = 2.0 }]
"""


@pytest.fixture(scope="module")
def moving_run(tmp_path_factory):
    d = tmp_path_factory.mktemp("moving")
    text = open(os.path.join(REPO, "tests", "scenes", "valid_minimal.toml")).read()
    text = text.replace("walls = true", "walls = true\nmoving_bodies = true\nrotating_bodies = true") + BODIES
    (d / "scene.toml").write_text(text)
    r = subprocess.run([dem2d_bin(), "run", str(d / "scene.toml"), "--out", str(d / "run"), "--threads", "1",
                        "--progress", "0"], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    return d / "run" / "run.h5"


def _value(name, v):
    def damage(f):
        attrs = dict(f[name].attrs)
        del f[name]
        f.create_dataset(name, data=np.asarray(v, dtype=float))
        f[name].attrs.update(attrs)
    return damage


PADDLE, TURNER = "parameters/bodies/1", "parameters/bodies/2"
DAMAGE = {
    "1e300 cycles": (_value(f"{PADDLE}/motion/0/cycles", 1e300), r"cycles: 1e\+300: must be a whole number from 1"),
    "2.5 cycles": (_value(f"{PADDLE}/motion/0/cycles", 2.5), "cycles: 2.5: must be a whole number from 1"),
    "a repeat past 32 bits": (_value(f"{PADDLE}/motion_repeat", 4294967297.0), "motion_repeat: .*: must be a whole number"),
    "an unknown kind": (lambda f: f[f"{PADDLE}/motion/0"].attrs.__setitem__("kind", "spin"),
                        "motion/0@kind: unknown motion kind 'spin'"),
    "a sine without its period": (lambda f: f.__delitem__(f"{PADDLE}/motion/0/period"), "motion/0/period: missing"),
    "a pivot of three values": (_value(f"{TURNER}/pivot", [0.01, 0.03, 0.0]), "pivot: 3 values, expected 2"),
    "a NaN angular velocity": (_value(f"{TURNER}/motion/1/angular_velocity", np.nan), "angular_velocity: nan: must be"),
}


def test_the_moving_run_passes_both_readers(moving_run):
    p = dem2d.open_run(moving_run).parameters
    paddle, turner = p.bodies[1], p.bodies[2]
    assert (paddle["name"], turner["name"]) == ("paddle", "turner")
    assert paddle["motion_repeat"] == 2 and paddle["motion"][0]["cycles"] == 2
    assert [s["kind"] for s in turner["motion"]] == ["hold", "ramp", "constant"]
    assert np.array_equal(turner["pivot"], [0.01, 0.03])
    r = subprocess.run([dem2d_bin(), "inspect", str(moving_run)], capture_output=True, text=True)
    assert r.returncode == 0 and "a sound run file" in r.stdout, r.stderr


@pytest.mark.parametrize("case", sorted(DAMAGE))
def test_damaged_motions_are_refused_by_both_readers(moving_run, tmp_path, case):
    damage, message = DAMAGE[case]
    path = tmp_path / "damaged.h5"
    path.write_bytes(moving_run.read_bytes())
    with h5py.File(path, "r+") as f:
        damage(f)
    pattern = f"damaged.h5: .*{message}"
    with dem2d.open_run(path) as run:
        with pytest.raises(dem2d.RunFileError, match=pattern):
            run.parameters
    r = subprocess.run([dem2d_bin(), "inspect", str(path)], capture_output=True, text=True)
    assert r.returncode == 2 and re.search(pattern, r.stderr), r.stderr
