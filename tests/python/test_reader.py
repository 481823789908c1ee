"""The Python reader (python/dem2d) on the examples' run files: what it resolves
(bodies of contacts, lines, heights) agrees with the engine's own records."""
import os
import re
import subprocess

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
    with pytest.raises(dem2d.RunFileError, match="other.h5: not a dem2d run file: format attribute is something-else"):
        dem2d.open_run(other)
    with pytest.raises(dem2d.RunFileError, match="missing.h5: no such file"):
        dem2d.open_run(tmp_path / "missing.h5")
    # a pipe blocked HDF5 for ever; a folder and a device are no run files either
    os.mkfifo(tmp_path / "pipe.h5")
    for path, kind in ((tmp_path / "pipe.h5", "a pipe"), (tmp_path, "a folder"), ("/dev/null", "a device")):
        with pytest.raises(dem2d.RunFileError, match=f"{kind}, not a regular file"):
            dem2d.open_run(path)


def _set(name, change):
    def damage(f):
        data = f[name][...]
        change(data)
        f[name][...] = data
    return damage


def _replace(name, data):
    def damage(f):
        attrs, new = dict(f[name].attrs), data(f)
        del f[name]
        f.create_dataset(name, data=new)
        f[name].attrs.update(attrs)
    return damage


# Damage, where the reader meets it, and the dataset its refusal must name. Both readers (this one and
# `dem2d inspect`, the analyses') refuse each, and the message names the file and the dataset.
DAMAGE = {
    "a shape that does not match": (_replace("snapshots/omega", lambda f: f["snapshots/omega"][:, :-1]), "open",
                                    "/snapshots/omega has shape"),
    "a contact on body 99 of 4": (_set("contacts/j", lambda j: j.__setitem__(-1, -100)), "snapshot",
                                  "contact row .* is not a contact"),
    "times going backwards": (_set("snapshots/time", lambda t: t.__setitem__(5, t[4] - 1)), "open",
                              "/snapshots/time is not strictly increasing"),
    "a NaN position": (_set("snapshots/position", lambda x: x.__setitem__((-1, 7, 0), np.nan)), "snapshot",
                       "/snapshots/position at snapshot .*: grain 7 holds NaN"),
    "grains far outside the domain": (_set("snapshots/position", lambda x: x.__setitem__((-1, slice(None), 0), 1e300)),
                                      "snapshot", r"/snapshots/position at snapshot .*: grain \d+ at \(1e\+300, .*"
                                      "active outside the domain"),
    "a wrong n_particles": (lambda f: f.attrs.__setitem__("n_particles", 5), "open",
                            "root attribute n_particles is 5, but the file holds"),
    "a missing dataset": (lambda f: f.__delitem__("contacts/fn"), "open", "/contacts/fn is missing"),
    # root attributes of one number damaged into a string or an array: raw ValueError/TypeError before, and
    # the C++ reader read an array into one value, past its end
    "n_particles a string": (lambda f: f.attrs.__setitem__("n_particles", "x"), "open",
                             "n_particles"),
    "n_bodies a float": (lambda f: f.attrs.__setitem__("n_bodies", np.nan), "open", "n_bodies"),
    "displacement_window an array": (lambda f: f.attrs.__setitem__("displacement_window", np.full(64, 0.05)), "open",
                                     "displacement_window"),
    # the run's end: the spectrum stage's exit height is read from it (a NaN blamed the stop criterion)
    "end_time NaN": (lambda f: f.attrs.__setitem__("end_time", np.nan), "open", "end_time = nan: must be a finite"),
    "end_time before the last snapshot": (lambda f: f.attrs.__setitem__("end_time", 1e-3), "open",
                                          "end_time = 0.001: must be a finite time .s. at or after"),
    "end_time after the last snapshot": (lambda f: f.attrs.__setitem__("end_time", 1e300), "open",
                                         "end_time = 1e.300: must be the time of the run's last snapshot"),
    "end_time missing": (lambda f: f.attrs.__delitem__("end_time"), "open", "root attribute end_time is missing"),
    "a series shorter than its times": (_replace("series/body_force_mean", lambda f: f["series/body_force_mean"][:-1]),
                                        "series", "/series/body_force_mean has shape"),
    "a law value out of its range": (_set("parameters/contact/grain_grain/kn", lambda v: v.__setitem__((), -1.0)),
                                     "parameters", "/parameters/contact/grain_grain/kn: -1: must be > 0"),
    "a missing law value": (lambda f: f.__delitem__("parameters/contact/grain_grain/friction"), "parameters",
                            "/parameters/contact/grain_grain/friction: missing"),
}


@pytest.mark.parametrize("case", sorted(DAMAGE))
def test_damaged_run_files_are_refused_by_both_readers_naming_the_file_and_dataset(example_runs, tmp_path, case):
    from conftest import dem2d_bin
    damage, where, message = DAMAGE[case]
    path = tmp_path / "damaged.h5"
    path.write_bytes(open(example_runs["pulloff"], "rb").read())
    with h5py.File(path, "r+") as f:
        damage(f)
    pattern = f"damaged.h5: .*{message}"
    if where == "open":
        with pytest.raises(dem2d.RunFileError, match=pattern):
            dem2d.open_run(path)
    else:
        with dem2d.open_run(path) as run:  # the file opens: the damage is met where it is read
            with pytest.raises(dem2d.RunFileError, match=pattern):
                {"snapshot": lambda: run.snapshot(-1), "series": lambda: run.series.body_force(run.body("intruder")),
                 "parameters": lambda: run.parameters}[where]()
    with pytest.raises(dem2d.RunFileError, match=pattern):
        dem2d.check_run(path)
    r = subprocess.run([dem2d_bin(), "inspect", str(path)], capture_output=True, text=True)
    assert r.returncode == 2 and re.search(pattern, r.stderr), r.stderr


def test_a_sound_run_file_passes_both_readers(example_runs):
    from conftest import dem2d_bin
    for path in example_runs.values():
        assert "a sound run file" in dem2d.check_run(path)
        r = subprocess.run([dem2d_bin(), "inspect", path], capture_output=True, text=True)
        assert r.returncode == 0 and "a sound run file" in r.stdout, r.stderr


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
    with pytest.raises(dem2d.RunFileError, match="old.h5: written by dem2d .* before run files carried their parameters"):
        dem2d.open_run(old)


def test_bodies_are_drawn_in_data_units_whenever_they_are_drawn(example_runs):
    """A body's drawing (its core swept by a disc of its thickness) does not depend on the axes' limits:
    drawn before or after the frame is set, the picture is the same."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np
    from dem2d.plot import draw_bodies, draw_grains, frame

    def picture(bodies_first):
        with dem2d.open_run(example_runs["pulloff"]) as run:
            s = run.snapshot(len(run) - 1)
            fig, ax = plt.subplots(figsize=(3, 3), dpi=80)
            if bodies_first:
                draw_bodies(ax, run, s)
            draw_grains(ax, run, s)
            frame(ax, run, s)
            if not bodies_first:
                draw_bodies(ax, run, s)
            fig.canvas.draw()
            image = np.asarray(fig.canvas.buffer_rgba()).copy()
            plt.close(fig)
            return image

    first, last = picture(True), picture(False)
    assert first.shape == last.shape
    assert np.array_equal(first, last)
    # and the bodies are there: the intruder's blue
    assert (np.abs(first[..., :3].astype(int) - [0x1f, 0x77, 0xb4]).sum(axis=-1) < 30).sum() > 20
