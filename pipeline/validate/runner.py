"""Scenes for the validation cases, written as a user would write them
(docs/scene_format.md), run with dem2d, and their run files read back."""
import json
import subprocess
from dataclasses import dataclass, field
from pathlib import Path

import dem2d  # the run-file reader (python/dem2d)
import numpy as np

from pipeline import tomlwrite

DENSITY = 2500.0  # kg/m^3, glass (docs/paper.md)


def disk_mass(d: float) -> float:
    """Mass per unit depth of a disk of diameter d (kg/m)."""
    return DENSITY * np.pi * d * d / 4.0


def glass_contact(kn: float, e: float = 0.9, mu: float = 0.5, kt_ratio: float = 0.5, **extra) -> dict:
    """The paper's law (docs/paper.md) at stiffness kn (N/m): k_t = k_n/2, e, mu; extra keys as given."""
    law = {"kn": kn, "kt": kt_ratio * kn, "restitution": e, "friction": mu}
    law.update(extra)
    return law


@dataclass
class Run:
    """A finished run: its directory and run file."""
    dir: Path
    file: Path = field(init=False)

    def __post_init__(self):
        self.file = self.dir / "run.h5"

    def read(self, name: str) -> np.ndarray:
        """Dataset `name` of the run file (e.g. "series/time"), read through dem2d.Run."""
        with dem2d.open_run(self.file) as r:
            return r.dataset(name)

    def attr(self, name: str):
        with dem2d.open_run(self.file) as r:
            return r.attrs[name]


def run(dem2d: str, scene: dict, out: Path, extra_args=()) -> Run:
    """Writes out/scene.toml and runs it into out/ (one thread); raises on failure."""
    out.mkdir(parents=True, exist_ok=True)
    path = out / "scene.toml"
    path.write_text(tomlwrite.dumps(scene))
    cmd = [dem2d, "run", str(path), "--out", str(out), "--threads", "1", "--fresh", "--overwrite",
           *extra_args]  # its own folder: run afresh each time
    done = subprocess.run(cmd, capture_output=True, text=True)
    if done.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)} failed ({done.returncode}):\n{done.stderr[-2000:]}")
    return Run(out)


def run_stage(dem2d: str, name: str, run_file: Path, out: Path, config: Path) -> None:
    """The analysis stage `name` of dem2d's build tree (build/<tree>/analysis/<name>) on run_file, into
    out/; raises on failure."""
    program = Path(dem2d).resolve().parents[1] / "analysis" / name
    if not program.is_file():
        raise FileNotFoundError(f"{program}: build the tree first (make build)")
    cmd = [str(program), str(run_file), "--out", str(out), "--config", str(config), "--threads", "1"]
    done = subprocess.run(cmd, capture_output=True, text=True)
    if done.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)} failed ({done.returncode}):\n{done.stderr[-2000:]}")


def ledger_terms(dem2d: str) -> dict:
    """The energy ledger's terms as the program names them (/series/energy/<term>), each with the sign it enters
    the conserved total with (dem2d inspect --schema: energy_balance)."""
    done = subprocess.run([dem2d, "inspect", "--schema"], capture_output=True, text=True)
    if done.returncode != 0:
        raise RuntimeError(f"{dem2d} inspect --schema failed: {done.stderr.strip()}")
    return json.loads(done.stdout)["energy_balance"]


def check(dem2d: str, scene: dict, out: Path) -> dict:
    """`dem2d check --json` of a scene (its stability limit, damping ratio ...)."""
    out.mkdir(parents=True, exist_ok=True)
    path = out / "scene.toml"
    path.write_text(tomlwrite.dumps(scene))
    done = subprocess.run([dem2d, "check", str(path), "--json"], capture_output=True, text=True)
    if done.returncode != 0:
        raise RuntimeError(f"dem2d check {path} failed:\n{done.stderr}")
    return json.loads(done.stdout)
