"""The Python reader (python/dem2d) on the examples' run files: what it resolves
(bodies of contacts, lines, heights) agrees with the engine's own records."""
import h5py
import numpy as np
import pytest

import dem2d


def test_every_dataset_has_units_and_a_description(example_runs):
    for path in example_runs.values():
        with dem2d.open_run(path) as run:
            names = []
            run.file.visititems(lambda n, o: names.append(n) if isinstance(o, h5py.Dataset) else None)
            assert len(names) > 40
            for n in names:
                assert run.units(n) and run.description(n), n
            assert run.units("contacts/fn") == "N/m"
            assert run.units("snapshots/position") == "m"
            assert run.units("series/body_torque") == "N"


def test_contacts_resolve_their_bodies_and_reproduce_the_engines_body_forces(example_runs):
    """The force of the grains on each body, summed over the reader's contacts of a snapshot, is
    the engine's /series/body_force at that step (N/m), wherever a series row falls on a snapshot."""
    checked = 0
    for path in example_runs.values():
        with dem2d.open_run(path) as run:
            series_step = run.series.step
            for k in range(len(run)):
                s = run.snapshot(k)
                row = np.flatnonzero(series_step == s.step)
                if not len(row):
                    continue
                c = s.contacts
                assert np.array_equal(c.is_body, c.j < 0)
                assert np.array_equal(c.body[c.is_body], -1 - c.j[c.is_body])
                assert np.all(c.grain_j[~c.is_body] == c.j[~c.is_body]) and np.all(c.grain_j[c.is_body] == -1)
                t = np.stack([-c.normal[:, 1], c.normal[:, 0]], axis=1)
                for b in run.bodies:
                    on = c.with_body(b)
                    force = -(c.fn[on, None] * c.normal[on] + c.ft[on, None] * t[on]).sum(axis=0)
                    engine = run.series["body_force"][row[0], b.index]
                    assert force == pytest.approx(engine, abs=1e-9 * max(1.0, np.abs(engine).max())), (k, b.name)
                checked += 1
    assert checked >= 5


def test_contact_lines_and_friction_mobilisation(example_runs):
    with dem2d.open_run(example_runs["pulloff"]) as run:
        r = run.particles.diameter / 2
        for k in (0, len(run) // 2):
            s = run.snapshot(k)
            c = s.contacts
            assert np.array_equal(c.line[:, 0], s.position[c.i])
            grains = ~c.is_body
            assert np.array_equal(c.line[grains, 1], s.position[c.grain_j[grains]])
            # on a body: the contact point, r - overlap/2 from the grain's centre against the normal
            reach = np.linalg.norm(c.line[c.is_body, 1] - c.line[c.is_body, 0], axis=1)
            assert reach == pytest.approx(r[c.i[c.is_body]] - c.overlap[c.is_body] / 2, rel=1e-12)
            # mu* on the Coulomb cone exactly when sliding
            assert np.nanmax(c.mu_star) <= 1 + 1e-12
            assert np.all(c.mu_star[c.sliding] > 1 - 1e-9)
            assert np.all(c.mu_star[~c.sliding & ~np.isnan(c.mu_star)] < 1)


def test_bodies_heights_and_snapshots(example_runs):
    with dem2d.open_run(example_runs["pulloff"]) as run:
        bar = run.body("intruder")
        assert (bar.name, bar.shape, bar.vertex_count, bar.thickness) == ("intruder", "rectangle", 4, 0.0)
        assert run.body("floor").role == "floor"
        assert run.floor_top() == pytest.approx(0.0, abs=1e-12)
        h = run.heights()
        assert h[0] == pytest.approx(0.001, abs=1e-9)  # the bar lies on the floor: its centre 1 mm up
        speed = np.polyfit(run.times, h, 1)[0]
        assert speed == pytest.approx(run.parameters.body("intruder")["velocity"][1], rel=1e-9)  # 20 mm/s
        assert run.snapshot(-1).time == run.times[-1] == run.snapshot(len(run) - 1).time
        assert run.snapshot_at(run.times[3] + 1e-6).index == 3
        with pytest.raises(KeyError, match="no body with role or name 'lid'"):
            run.body("lid")
        with pytest.raises(IndexError):
            run.snapshot(len(run))


def test_what_is_not_a_run_file_is_refused(tmp_path):
    other = tmp_path / "other.h5"
    with h5py.File(other, "w") as f:
        f.attrs["format"] = "something-else"
    with pytest.raises(ValueError, match="other.h5: format 'something-else' is not a dem2d run file"):
        dem2d.open_run(other)
    with pytest.raises(OSError, match="missing.h5: cannot open as a run file"):
        dem2d.open_run(tmp_path / "missing.h5")


def test_parameters_are_the_scenes_typed_with_units(example_runs, tmp_path):
    with dem2d.open_run(example_runs["pulloff"]) as run:
        p = run.parameters
        assert p.effects >= {"gravity", "friction", "walls", "moving_bodies"}
        assert p.contact["grain_grain"]["kn"] == 1.92e6 and p.units["contact/grain_grain/kn"] == "N/m"
        assert p.contact["grain_grain"]["friction"] == 0.5 and p.contact["grain_body"]["friction"] == 0.5
        assert "cohesion_force" not in p.contact["grain_grain"]  # its effect is off
        assert p.dt == run.dt and p.units["time/dt"] == "s"
        assert list(p.body("intruder")["velocity"]) == [0.0, 0.02] and p.units["bodies/3/velocity"] == "m/s"
        assert p.stop["body_free"] == "intruder" and p.stop["free_time"] > 0
    # a run file from before /parameters is refused, saying how to regenerate it
    old = tmp_path / "old.h5"
    old.write_bytes(open(example_runs["box"], "rb").read())
    with h5py.File(old, "a") as f:
        del f["parameters"]
    with pytest.raises(ValueError, match="old.h5: written by dem2d .* before run files carried their parameters"):
        dem2d.open_run(old)
