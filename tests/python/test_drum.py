"""The rotating drum (examples/drum): walls turned by their schedule drive the bed.

- the dynamic angle of repose rises with the Froude number Fr = omega^2 R / g
  (the rolling regime's flat surface steepens as the drum turns faster;
  e.g. GDR MiDi, Eur. Phys. J. E 14, 341 (2004), section on rotating drums):
  at Fr = 0.3 it is steeper than at Fr = 0.01 by more than 2.5 deg and by more
  than three standard errors of the difference;
- the torque in the run's series balances gravity's: in steady rotation the
  grains' torque on the drum about its axis is -g M x_com (x_com: the bed's
  centre of mass, horizontally from the axis);
- above Fr = 1 the bed centrifuges: it turns with the drum as a rigid body
  (its angular momentum over its moment of inertia is omega, its grains spin at omega).
"""
import csv
import os
import subprocess
import sys

import pytest

from conftest import REPO, dem2d_bin

FROUDE = os.path.join(REPO, "examples", "drum", "froude.py")


def sweep(out, *args):
    r = subprocess.run([sys.executable, FROUDE, dem2d_bin(), str(out), *args], capture_output=True, text=True)
    assert r.returncode == 0, r.stdout + r.stderr
    print(r.stdout)
    with open(os.path.join(out, "froude.csv")) as f:
        return [{k: float(v) for k, v in row.items()} for row in csv.DictReader(f)]


def test_angle_of_repose_rises_with_the_froude_number_and_the_torque_balances(tmp_path):
    slow, fast = sweep(tmp_path, "--froude", "0.01", "0.3", "--turn", "8")
    assert slow["froude"] == pytest.approx(0.01, rel=1e-3) and fast["froude"] == pytest.approx(0.3, rel=1e-3)
    assert 20.0 < slow["angle_deg"] < 36.0, slow  # disks with rolling resistance, mu = 0.5
    rise = fast["angle_deg"] - slow["angle_deg"]
    error = (slow["angle_se_deg"] ** 2 + fast["angle_se_deg"] ** 2) ** 0.5
    assert rise > 2.5 and rise > 3.0 * error, (slow, fast)
    for row in (slow, fast):
        assert row["torque"] == pytest.approx(row["gravity_torque"], rel=0.03), row
    assert os.path.getsize(tmp_path / "froude.png") > 10_000
    # the example's own script on the Fr = 0.01 run: the same angle, and its picture
    r = subprocess.run([sys.executable, os.path.join(REPO, "examples", "drum", "plot.py"),
                        str(tmp_path / "fr_0.01" / "run" / "run.h5"), str(tmp_path / "drum.png")],
                       capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    assert f"dynamic angle of repose {slow['angle_deg']:.2f} +- " in r.stdout, r.stdout
    assert os.path.getsize(tmp_path / "drum.png") > 10_000


def test_above_froude_one_the_bed_turns_rigidly_with_the_drum(tmp_path):
    (row,) = sweep(tmp_path, "--froude", "3", "--turn", "40", "--settle", "30")
    assert row["bed_omega"] / row["omega"] == pytest.approx(1.0, abs=0.02), row
    assert row["spin"] / row["omega"] == pytest.approx(1.0, abs=0.05), row
