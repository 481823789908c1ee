"""Shared helpers of the figure scripts: the stage files of a results
directory (with errors that name the file and the make target producing it),
a few study constants, the common style, and atomic writing."""

import json
import os
import sys
import tomllib
from pathlib import Path

import dem2d
import matplotlib

from pipeline.files import stages, write_atomic

matplotlib.use("Agg")
import h5py  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

DPI = 110
MM = 1e3  # m -> mm
REPO = Path(__file__).resolve().parents[2]
STUDY_FILE = REPO / "data" / "study.toml"

# stage -> the files of it that the figures read: every stage's outputs
# (pipeline/stages.toml), and the pull-off's run file, which they draw
STAGE_FILES = {s.name: (["run.h5"] if s.name == "pulloff" else []) + s.outputs for s in stages()}

# the three mobility zones of v* = |V|/V (docs/paper.md, paper Fig. 8)
ZONE_COLOURS = ["#3b6fd8", "#3fae49", "#d8403b"]

plt.rcParams.update({
    "font.size": 9, "axes.titlesize": 9, "axes.labelsize": 9, "legend.fontsize": 8,
    "xtick.labelsize": 8, "ytick.labelsize": 8, "figure.dpi": DPI, "savefig.dpi": DPI,
    "image.cmap": "viridis",
})


class InputError(Exception):
    """A missing or unreadable input; the message says which make target makes it."""


class NoData(Exception):
    """The stage outputs hold nothing a figure could draw; the message says what is missing."""


class H5:
    """An HDF5 input whose missing datasets are reported with the file and the target."""

    def __init__(self, path, target):
        self.path, self.target = path, target
        try:
            self.f = h5py.File(path, "r")
        except OSError as e:
            raise InputError(f"{path} unreadable ({e}): run `{target}`") from e

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.f.close()

    def has(self, name):
        return name in self.f

    def dset(self, name):
        if name not in self.f:
            raise InputError(f"{self.path}: dataset /{name} missing: run `{self.target}` "
                             "(with the current stage program)")
        return self.f[name]

    def read(self, name, index=()):
        return self.dset(name)[index]

    def attr(self, name, default=None, where="/"):
        return self.f[where].attrs.get(name, default)


class Metrics(dict):
    """A stage's metrics; a missing key is an InputError naming the file and the target."""

    def __init__(self, values, where, target):
        super().__init__(values)
        self.where, self.target = where, target

    def __missing__(self, key):
        raise InputError(f"{self.where} has no '{key}': run `{self.target}` (with the current stage program)")


class Inputs:
    """The stage files of one results directory, e.g. results/default."""

    def __init__(self, results_dir):
        self.dir = Path(results_dir)
        self.preset = self.dir.resolve().name
        self._metrics = {}

    def path(self, stage, name):
        return self.dir / stage / name

    def target(self, stage):
        return f"make {stage} PRESET={self.preset}"

    def missing(self, stage, name, why="missing"):
        return InputError(f"{self.path(stage, name)} {why}: run `{self.target(stage)}`")

    def check(self):
        """Every input exists and opens; raises InputError on the first that does not."""
        for stage, names in STAGE_FILES.items():
            for name in names:
                p = self.path(stage, name)
                if not p.is_file():
                    raise self.missing(stage, name)
                if name == "run.h5":  # the run-file reader's checks (python/dem2d)
                    try:
                        dem2d.Run(p).close()
                    except (OSError, ValueError) as e:
                        raise InputError(f"{e}: run `{self.target(stage)}`") from e
                elif name.endswith(".h5"):
                    self.h5(stage, name).f.close()
                else:
                    self.metrics(stage)

    def h5(self, stage, name):
        p = self.path(stage, name)
        if not p.is_file():
            raise self.missing(stage, name)
        return H5(p, self.target(stage))

    def metrics(self, stage):
        """The stage's metrics.json, the object under its stage name."""
        if stage not in self._metrics:
            p = self.path(stage, "metrics.json")
            try:
                with open(p) as f:
                    self._metrics[stage] = Metrics(json.load(f)[stage], p, self.target(stage))
            except FileNotFoundError as e:
                raise self.missing(stage, "metrics.json") from e
            except (OSError, ValueError, KeyError, TypeError) as e:
                raise self.missing(stage, "metrics.json", f"unreadable ({e!r})") from e
        return self._metrics[stage]


def study():
    """data/study.toml as a dict."""
    try:
        with open(STUDY_FILE, "rb") as f:
            return tomllib.load(f)
    except (OSError, tomllib.TOMLDecodeError) as e:
        raise InputError(f"{STUDY_FILE} unreadable ({e})") from e


def intruder_depth(inp):
    """W (m): from the pull-off metrics, else data/study.toml."""
    w = inp.metrics("pulloff").get("intruder_depth_W_m")
    return w if w else study()["experiment"]["intruder_depth"]


def bed_height_mm(inp):
    return inp.metrics("fill")["bed_height_mm"]


def band_mm(inp, name):
    """[low, high] (mm) of a spectrum height band (bottom, middle, upper, top_layer), or NaNs."""
    band = (inp.metrics("spectrum").get("bands") or {}).get(name) or {}
    return band.get("range_mm") or [np.nan, np.nan]


def nearest(values, target, allowed=None):
    """Index of the value nearest to target (among the allowed indices)."""
    idx = np.arange(len(values)) if allowed is None else np.asarray(allowed)
    if len(idx) == 0:
        return None
    return int(idx[np.argmin(np.abs(np.asarray(values)[idx] - target))])


def binned_fraction(height, flag, lower, upper):
    """Mean of flag over the samples with lower <= height < upper, per bin (NaN if none)."""
    out = np.full(len(lower), np.nan)
    for b, (lo, hi) in enumerate(zip(lower, upper)):
        sel = (height >= lo) & (height < hi)
        if sel.any():
            out[b] = np.mean(flag[sel])
    return out


def mark_heights(ax, marks, vertical=True):
    """Dashed lines at named heights (mm): [(value, label, colour)], skipping None."""
    for value, label, colour in marks:
        if value is None or not np.isfinite(value):
            continue
        line = ax.axvline if vertical else ax.axhline
        line(value, ls="--", lw=0.9, color=colour, label=label)


def fmt(value, spec=".1f", unit=" mm"):
    """A number for a caption, or "n/a" when a stage reported null."""
    return "n/a" if value is None else f"{value:{spec}}{unit}"


def save(fig, outdir, name, stamp=""):
    """Write the PNG under a temporary name, then rename it; `stamp` (what made it) in its lower right corner."""
    if stamp:
        fig.text(0.995, 0.003, stamp, ha="right", va="bottom", fontsize=6, color="0.45")
    tmp = os.path.join(outdir, f".{name}.tmp")
    try:
        fig.savefig(tmp, format="png", dpi=DPI)
        os.replace(tmp, os.path.join(outdir, name))
    except OSError as e:  # a full disk: no half-written figure, a message instead of a traceback
        if os.path.exists(tmp):
            os.remove(tmp)
        print(f"{os.path.join(outdir, name)}: cannot write it ({e.strerror or e}); nothing was left half-written",
              file=sys.stderr)
        sys.exit(2)
    finally:
        plt.close(fig)


def write_json(obj, path):
    write_atomic(Path(path), json.dumps(obj, indent=2, ensure_ascii=False) + "\n")
