"""Scenes for the validation cases, written as a user would write them
(docs/scene_format.md), run with dem2d, and their run files read back."""
import json
import subprocess
from dataclasses import dataclass, field
from pathlib import Path

import sys

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "python"))
import dem2d  # noqa: E402  (the run-file reader, python/dem2d)

DENSITY = 2500.0  # kg/m^3, glass (docs/paper.md)


def disk_mass(d: float) -> float:
    """Mass per unit depth of a disk of diameter d (kg/m)."""
    return DENSITY * np.pi * d * d / 4.0


def toml_value(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, str):
        return json.dumps(v)
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(toml_value(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{ " + ", ".join(f"{k} = {toml_value(x)}" for k, x in v.items()) + " }"
    return repr(float(v)) if isinstance(v, float) else str(v)


def toml_text(scene: dict) -> str:
    """A scene dict as TOML: scalars first, then tables, then arrays of tables."""
    lines = [f"{k} = {toml_value(v)}" for k, v in scene.items() if not isinstance(v, (dict, list)) or
             (isinstance(v, list) and not (v and isinstance(v[0], dict)))]

    def table(prefix: str, t: dict) -> None:
        lines.append(f"[{prefix}]")
        lines.extend(f"{k} = {toml_value(v)}" for k, v in t.items() if not isinstance(v, dict) or k in ("diameter",))
        for k, v in t.items():
            if isinstance(v, dict) and k not in ("diameter",):
                table(f"{prefix}.{k}", v)

    for k, v in scene.items():
        if isinstance(v, dict):
            table(k, v)
    for k, v in scene.items():
        if isinstance(v, list) and v and isinstance(v[0], dict):
            for entry in v:
                lines.append(f"[[{k}]]")
                lines.extend(f"{kk} = {toml_value(vv)}" for kk, vv in entry.items())
    return "\n".join(lines) + "\n"


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
    path.write_text(toml_text(scene))
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


def check(dem2d: str, scene: dict, out: Path) -> dict:
    """`dem2d check --json` of a scene (its stability limit, damping ratio ...)."""
    out.mkdir(parents=True, exist_ok=True)
    path = out / "scene.toml"
    path.write_text(toml_text(scene))
    done = subprocess.run([dem2d, "check", str(path), "--json"], capture_output=True, text=True)
    if done.returncode != 0:
        raise RuntimeError(f"dem2d check {path} failed:\n{done.stderr}")
    return json.loads(done.stdout)
