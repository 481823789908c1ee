"""The run file: a Run and what it holds (snapshots, contacts, bodies, series)."""
from __future__ import annotations

import os
import stat
from dataclasses import dataclass, field
from functools import cached_property

import h5py
import numpy as np

from . import schema
from .checks import SERIES, Checker, RunFileError, check_contacts, check_parameter, check_parameter_keys, \
    check_series_dataset, check_structure



def open_run(path):
    """A Run for the run file at `path` (use it in a with-statement, or call close()).
    RunFileError if it is damaged or not a run file (the message names the file and the dataset)."""
    return Run(path)


def check_run(path):
    """Reads the whole run file with every check (as `dem2d inspect` does); RunFileError at the first problem.
    Returns a one-line summary."""
    with Run(path) as run:
        run.parameters
        if "series" in run.file:
            for name in SERIES:
                run._c.need(f"series/{name}")
        for name in run.series.names():
            run.series[name]
        if "bodies/velocity" in run.file:
            run._c.finite("bodies/velocity", run.file["bodies/velocity"][...])
        if "contacts/line" in run.file:
            run._c.finite("contacts/line", run.file["contacts/line"][...])
        contacts = sum(len(s.contacts) for s in run)
        return (f"{run.path}: a sound run file of scene {run.parameters.name}: {run.n_particles} grains, "
                f"{len(run.bodies)} bodies, {len(run)} snapshots, {len(run.series.time)} series rows, "
                f"{contacts} contact rows")


@dataclass(frozen=True)
class Body:
    """A wall or moving body: a convex core (a point, a segment or a polygon) rounded by thickness/2."""
    index: int
    name: str
    role: str          # intruder, floor, left_wall, right_wall, hopper, or ""
    shape: str         # its shape kind (segment, rectangle, polygon, ...)
    thickness: float   # m
    vertex_count: int

    def core(self, body_vertices):
        """This body's core vertices (x, y) in m from a snapshot's or series row's body_vertices [B, K, 2]."""
        return np.asarray(body_vertices)[self.index, :self.vertex_count]


@dataclass(frozen=True)
class Parameters:
    """What the run ran with: the run file's /parameters (docs/run_file.md), typed, SI.

    contact["grain_grain"], contact["grain_body"]: the law's values by scene key (kn, friction, ...);
    stop, output: by key (s, J/m, m); bodies: one dict each (name, role, shape, vertices [K, 2] m,
    thickness m, velocity [2] m/s, remove_at s or None, motion: a list of segment dicts with "kind",
    motion_repeat); units[path]: the unit of every value, path as in the file ("contact/grain_grain/kn")."""
    name: str
    effects: frozenset
    dt: float
    density: float
    gravity: np.ndarray
    contact: dict
    stop: dict
    output: dict
    domain: np.ndarray
    skin: float
    bodies: list
    jam: dict        # the hopper's jam remedy ([jam]: outlet_height m, ..., bodies), {} without
    units: dict = field(repr=False)

    def body(self, role):
        """The body dict with this role; KeyError naming the roles there are."""
        for b in self.bodies:
            if b["role"] == role:
                return b
        raise KeyError(f"no body has the role {role!r} (roles: {sorted({b['role'] for b in self.bodies})})")


def motion_count(c: Checker, name: str, v: float) -> int:
    """A motion's cycles or motion_repeat: a whole number from 1 to the schema's max_motion_pieces (the
    scene's range)."""
    most = schema.parameters()["max_motion_pieces"]
    if not (1 <= v <= most and float(v).is_integer()):
        c.fail(f"/{name}: {v:g}: must be a whole number from 1 to {most}")
    return int(v)


def _read_parameters(c: Checker, g: h5py.Group) -> Parameters:
    try:
        return _parameters(c, g)
    except RunFileError:
        raise
    except (KeyError, ValueError, TypeError) as e:
        c.fail(f"/parameters is incomplete or damaged: {e}")


def _parameters(c: Checker, g: h5py.Group) -> Parameters:
    units = {}

    def values(group):
        out = {}
        for k, v in group.items():
            if isinstance(v, h5py.Dataset) and h5py.check_string_dtype(v.dtype) is None:
                x = check_parameter(c, v)
                out[k] = float(x) if np.ndim(x) == 0 else np.asarray(x, dtype=float)
                units[v.name[len("/parameters/"):]] = v.attrs.get("units", "-")
        return out

    fmt, known = g.attrs.get("format"), schema.parameters()["format"]
    if fmt != known:
        c.fail(f"/parameters has format {fmt!r}; this reader knows {known}")
    check_parameter_keys(c, g)
    if "free_time" in g["stop"] and "body_free" not in g["stop"].attrs:
        c.fail("/parameters/stop@body_free: missing (the body whose freedom ends the run)")
    bodies = []
    for k in range(int(g.attrs["bodies"])):
        b = g[f"bodies/{k}"]
        d = {"name": b.attrs["name"], "role": b.attrs["role"], "shape": b.attrs["shape"], **values(b)}
        d["remove_at"] = d.get("remove_at")
        d["vertices"] = np.asarray(d["vertices"]).reshape(-1, 2)
        d["motion"] = ([{"kind": b[f"motion/{j}"].attrs["kind"], **values(b[f"motion/{j}"])}
                        for j in range(int(b["motion"].attrs["segments"]))] if "motion" in b else [])
        for j, seg in enumerate(d["motion"]):
            where = f"/parameters/bodies/{k}/motion/{j}"
            kinds = schema.parameters()["motion_kinds"]  # the values each kind must have (a last constant
            if seg["kind"] not in kinds:                 # segment without a duration goes on for ever)
                c.fail(f"{where}@kind: unknown motion kind {seg['kind']!r}")
            for key in kinds[seg["kind"]]:
                forever = key == "duration" and seg["kind"] == "constant" and j + 1 == len(d["motion"])
                if key not in seg and not forever:
                    c.fail(f"{where}/{key}: missing")
            if "cycles" in seg:
                seg["cycles"] = motion_count(c, f"parameters/bodies/{k}/motion/{j}/cycles", seg["cycles"])
        d["motion_repeat"] = (motion_count(c, f"parameters/bodies/{k}/motion_repeat", d["motion_repeat"])
                              if "motion_repeat" in d else 1)
        bodies.append(d)
    effects = values(g["effects"])
    return Parameters(
        name=g.attrs["scene"], effects=frozenset(k for k, on in effects.items() if on),
        dt=values(g["time"])["dt"], density=values(g["material"])["density"],
        gravity=values(g["gravity"])["g"] if "gravity" in g else np.zeros(2),
        contact={k: values(g["contact"][k]) for k in g["contact"]},
        stop={**values(g["stop"]), **({"body_free": g["stop"].attrs["body_free"]} if "body_free" in g["stop"].attrs else {})},
        output=values(g["output"]), domain=check_parameter(c, g["domain"]), skin=values(g["neighbour"])["skin"],
        bodies=bodies, jam=({**values(g["jam"]), "bodies": list(g["jam/bodies"].asstr()[...])} if "jam" in g else {}),
        units=units)


@dataclass(frozen=True)
class Particles:
    diameter: np.ndarray  # m [N]
    mass: np.ndarray      # kg/m [N]
    inertia: np.ndarray   # kg m [N]


class Contacts:
    """The acting contacts of one snapshot, one row each (grain-grain first, then grain-body).

    i: grain; j: the raw partner code of the file (j >= 0 a grain, else body -1-j);
    grain_j: the partner grain or -1; body: the partner body's index or -1; is_body: body contacts.
    fn, ft (N/m), overlap (m), normal [C, 2] (from the partner to grain i), mr (N), sliding (bool),
    mu_star (|ft| / (mu F_load), NaN without friction), line [C, 2, 2] (m: grain i's centre to the
    partner grain's centre or to the contact point on a body)."""

    def __init__(self, rows: dict):
        self.i = rows["i"]
        self.j = rows["j"]
        self.is_body = self.j < 0
        self.grain_j = np.where(self.is_body, -1, self.j)
        self.body = np.where(self.is_body, -1 - self.j, -1)
        self.fn, self.ft, self.overlap, self.mr = rows["fn"], rows["ft"], rows["overlap"], rows["mr"]
        self.normal = np.stack([rows["nx"], rows["ny"]], axis=-1) if len(self.i) else np.zeros((0, 2))
        self.sliding = rows["sliding"].astype(bool)
        self.mu_star = rows.get("mu_star")
        self.line = rows.get("line")

    def __len__(self):
        return len(self.i)

    def with_body(self, body: Body):
        """Mask of the contacts on `body`."""
        return self.body == body.index


@dataclass
class Snapshot:
    index: int
    time: float             # s
    step: int
    position: np.ndarray    # m [N, 2]
    velocity: np.ndarray    # m/s [N, 2]
    omega: np.ndarray       # rad/s [N]
    theta: np.ndarray       # rad [N]
    active: np.ndarray      # bool [N]
    body_vertices: np.ndarray  # m [B, K, 2]
    contacts: Contacts


class Series:
    """The time series (one row per series interval): time (s), step, and per body force/torque.
    Every dataset handed out is checked: one row per series time, numbers, floats finite."""

    def __init__(self, checker: Checker, time, sizes):
        self._c, self.time, self._sizes = checker, time, sizes
        self._g = checker.f["series"] if "series" in checker.f else {}
        self.step = self["step"] if "series/step" in checker.f else np.zeros(0, dtype=np.int64)

    def __getitem__(self, name):
        """Any series dataset by name, e.g. series["kinetic_energy"] or series["energy/sliding"]."""
        return check_series_dataset(self._c, name, self._sizes)

    def names(self):
        out = []
        if self._g:
            self._g.visititems(lambda n, o: out.append(n) if isinstance(o, h5py.Dataset) else None)
        return out

    def body_force(self, body: Body, mean=True):
        """[T, 2] force (fx, fy) of the grains on `body` (N/m): the mean over each interval, or the
        value at the row's step (mean=False)."""
        return self["body_force_mean" if mean else "body_force"][:, body.index, :]

    def body_torque(self, body: Body, mean=True):
        return self["body_torque_mean" if mean else "body_torque"][:, body.index]

    def body_vertices(self, body: Body):
        """[T, vertex_count, 2] core vertices of `body` (m)."""
        return self["body_vertices"][:, body.index, :body.vertex_count, :]


class Run:
    """A run file, opened read-only, its structure checked (dem2d.checks). Snapshots are read, and
    their values checked, when asked for. Every refusal is a RunFileError naming the file and dataset."""

    def __init__(self, path):
        self.path = str(path)
        if os.path.exists(self.path) and not os.path.isfile(self.path):  # a pipe or a device would block HDF5
            kind = "a folder" if os.path.isdir(self.path) else "a pipe" if stat.S_ISFIFO(os.stat(self.path).st_mode) \
                else "a device"
            raise RunFileError(f"{self.path}: {kind}, not a regular file: an HDF5 file is one")
        try:
            self.file = h5py.File(self.path, "r")
        except FileNotFoundError:
            raise RunFileError(f"{self.path}: no such file") from None
        except OSError as e:
            raise RunFileError(f"{self.path}: cannot open as a run file (HDF5): {e}") from None
        self._c = Checker(self.path, self.file)
        try:
            self._dims = self._checked(check_structure, self._c)
        except BaseException:
            self.file.close()
            raise
        self.attrs = {k: (v.item() if isinstance(v, np.generic) else v) for k, v in self.file.attrs.items()}
        self._start, self.times = self._dims["start"], self._dims["times"]

    def _checked(self, fn, *args):
        """fn(*args), HDF5's own read errors (a cut or damaged file) as RunFileError naming the file."""
        try:
            return fn(*args)
        except RunFileError:
            raise
        except (OSError, KeyError) as e:
            self._c.fail(f"cannot read: {e}")

    def close(self):
        self.file.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def __repr__(self):
        return (f"<dem2d.Run {self.path}: {self.n_particles} grains, {len(self.bodies)} bodies, "
                f"{len(self)} snapshots to t = {self.end_time:g} s>")

    # --- the run as a whole -------------------------------------------------
    @property
    def dt(self):
        return self.attrs["dt"]

    @property
    def end_time(self):
        return self.attrs["end_time"]

    @property
    def n_particles(self):
        return self._dims["N"]

    @property
    def stop_reason(self):
        """Why the run ended, in words."""
        return self.attrs["stop_reason"]

    @property
    def stopped_by(self):
        """The criterion that ended it: "duration", "body_free", "kinetic_energy", "max_taps"."""
        return self.attrs.get("stopped_by", "")

    def dataset(self, name):
        """A whole dataset by its path in the file (docs/run_file.md), e.g. "contacts/mu_star": as stored,
        its shape checked on opening where the format fixes it, its values not (series[...] and
        snapshot(k) check them)."""
        if name not in self.file or not isinstance(self.file[name], h5py.Dataset):
            raise KeyError(f"{self.path}: no dataset /{name}")
        return self._checked(lambda: self.file[name][...])

    @cached_property
    def parameters(self) -> Parameters:
        """What the run ran with (/parameters): the laws, bodies and schedules, time step, stop criteria."""
        return self._checked(_read_parameters, self._c, self.file["parameters"])

    @cached_property
    def particles(self) -> Particles:
        p = self.file["particles"]
        N = self._dims["N"]
        inertia = p["inertia"][...] if "inertia" in p else np.full(N, np.nan)
        return Particles(p["diameter"][...], p["mass"][...], inertia)

    @cached_property
    def bodies(self) -> list[Body]:
        b = self.file["bodies"]
        names, roles, shapes = (b[k].asstr()[...] for k in ("name", "role", "shape"))
        counts = b["vertex_count"][...]
        return [Body(k, str(names[k]), str(roles[k]), str(shapes[k]), float(b["thickness"][k]), int(counts[k]))
                for k in range(len(names))]

    def body(self, key: str) -> Body:
        """The body with this role (intruder, floor, left_wall, right_wall) or name."""
        for by in ("role", "name"):
            found = [b for b in self.bodies if getattr(b, by) == key]
            if found:
                return found[0]
        raise KeyError(f"{self.path}: no body with role or name {key!r} "
                       f"(bodies: {', '.join(b.name + (f' ({b.role})' if b.role else '') for b in self.bodies)})")

    def _outlines(self, b: Body):
        """[S, vertex_count, 2] body b's core at every snapshot (m), checked finite."""
        v = self._checked(lambda: self.file["snapshots/body_vertices"][:, b.index, :b.vertex_count, :])
        return self._c.finite("snapshots/body_vertices", v, "snapshot")

    def floor_top(self) -> float:
        """Height of the floor's face (m): the top of its rounded core."""
        floor = self.body("floor")
        if not len(self):
            self._c.fail("the run file has no snapshots (/snapshots/time is empty)")
        return float(self._outlines(floor)[0, :, 1].max() + floor.thickness / 2)

    def heights(self, body="intruder"):
        """[S] height of a body's centre (the mean of its core's vertices) above the floor's face, per snapshot (m):
        the study's intruder height H."""
        return self._outlines(self.body(body))[:, :, 1].mean(axis=1) - self.floor_top()

    @cached_property
    def series(self) -> Series:
        """The time series; empty (no rows) if the run wrote none."""
        time = self._checked(lambda: self.file["series/time"][...]) if "series/time" in self.file else np.zeros(0)
        return self._checked(Series, self._c, time, self._dims)

    def units(self, path: str) -> str:
        """The unit of a dataset, e.g. units("contacts/fn") == "N/m"."""
        return self.file[path].attrs["units"]

    def description(self, path: str) -> str:
        return self.file[path].attrs["description"]

    # --- snapshots ----------------------------------------------------------
    def __len__(self):
        return len(self.times)

    def snapshot(self, k: int) -> Snapshot:
        """Snapshot k (negative counts from the end)."""
        n = len(self.times)
        if not -n <= k < n:
            raise IndexError(f"{self.path}: snapshot {k} of {n}")
        k %= n
        return self._checked(self._snapshot, k)

    def _snapshot(self, k):
        s, c = self.file["snapshots"], self._c
        at = f" at snapshot {k}"
        position = c.finite("snapshots/position" + at, s["position"][k], "grain")
        velocity = c.finite("snapshots/velocity" + at, s["velocity"][k], "grain")
        omega = c.finite("snapshots/omega" + at, s["omega"][k], "grain")
        theta = c.finite("snapshots/theta" + at, s["theta"][k], "grain") if "theta" in s else np.zeros_like(omega)
        outlines = c.finite("snapshots/body_vertices" + at, s["body_vertices"][k], "body")
        active = s["active"][k].astype(bool)
        xmin, ymin, xmax, ymax = self.parameters.domain  # (the engine removes a grain whose centre leaves it)
        outside = active & ((position[:, 0] < xmin) | (position[:, 0] > xmax) | (position[:, 1] < ymin) |
                            (position[:, 1] > ymax))
        for i in np.flatnonzero(outside)[:1]:
            c.fail(f"dataset /snapshots/position at snapshot {k}: grain {i} at ({position[i, 0]:g}, {position[i, 1]:g}) m "
                   "is active outside the domain (/parameters/domain): a run keeps only grains inside it")
        return Snapshot(k, float(self.times[k]), int(s["step"][k]), position, velocity, omega, theta, active,
                        outlines, self.contacts(k))

    def snapshot_at(self, time: float) -> Snapshot:
        """The snapshot nearest to `time` (s)."""
        return self.snapshot(int(np.argmin(np.abs(self.times - time))))

    def __iter__(self):
        for k in range(len(self.times)):
            yield self.snapshot(k)

    def contacts(self, k: int) -> Contacts:
        """Snapshot k's contacts, checked (finite values; i, j and sliding in range)."""
        a, b = int(self._start[k]), int(self._start[k + 1])
        g = self.file["contacts"]
        rows = self._checked(lambda: {name: g[name][a:b] for name in g if isinstance(g[name], h5py.Dataset)})
        check_contacts(self._c, k, a, rows, self._dims["N"], self._dims["B"])
        return Contacts(rows)
