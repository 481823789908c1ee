"""dem2d against LAMMPS (GRANULAR package) on the same settled bed.

Usage: compare.py DESCRIPTION DEM2D OUT_DIR

From one description (data/bench/compare.toml) it writes the dem2d scenes and
the LAMMPS input, settles the bed once with dem2d, then runs both codes from
that bed for the same number of steps with 1 and 2 cores (dem2d: OpenMP
threads, LAMMPS: MPI ranks), and writes OUT_DIR/compare.json and
OUT_DIR/compare.md: ns per particle-step of each, the ratio, and whether the
two runs end in the same state (mean contact number, mean height), so that the
comparison is of equal work. Exit status 1 if they do not agree.

The contact laws are made identical where the codes allow:
- normal: k_n delta - eta v_n with eta = 2 nu sqrt(m_eff k_n). LAMMPS's
  `damping tsuji` has this form with its own fit alpha(e) for 2 nu; the
  restitution handed to LAMMPS is the e' with alpha(e') = 2 nu, nu being
  the damping ratio dem2d uses for the scene's e (`dem2d check --json`: the
  non-attractive law's, contact/contact_law.hpp). `limit_damping` keeps the
  normal force non-attractive, as in dem2d.
- tangential: an incremental spring k_t with a Coulomb cap mu F_n, no
  tangential damping (LAMMPS `linear_history k_t 0 mu`).
- disks of unit depth: mass rho pi r^2 (`set density/disc`), I = m r^2 / 2
  (`fix nve/sphere disc`), walls as planes at the cell's inner faces.
Known differences, too small to matter at this tolerance: LAMMPS starts with
no tangential history (dem2d carries the settled bed's), and its tangential
velocity uses the radii instead of the branch vectors to the contact point.
"""

import json
import os
import re
import shutil
import subprocess
import sys
import time
from pathlib import Path

import dem2d
import numpy as np

from pipeline import tomlwrite
from pipeline.files import fail, read_toml, write_atomic

WALL = 2e-3  # m, thickness of dem2d's wall sphero-lines (their inner faces are the cell's)


def tsuji_alpha(e: float) -> float:
    """LAMMPS's fit of the damping prefactor to the restitution coefficient."""
    return 1.2728 - 4.2783 * e + 11.087 * e**2 - 22.348 * e**3 + 27.467 * e**4 - 18.022 * e**5 + 4.8218 * e**6


def lammps_restitution(two_nu: float) -> float:
    """The e' for which LAMMPS's tsuji alpha equals dem2d's damping prefactor 2 nu."""
    lo, hi = 0.0, 1.0  # alpha falls from 1.27 to 3e-4 over [0, 1]
    if not tsuji_alpha(hi) < two_nu < tsuji_alpha(lo):
        fail(f"no restitution for LAMMPS's tsuji damping gives 2 nu = {two_nu}")
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if tsuji_alpha(mid) > two_nu else (lo, mid)
    return 0.5 * (lo + hi)


def dem2d_damping_ratio(dem2d: str, scene: Path, initial: Path) -> float:
    """The normal damping ratio dem2d uses for the scene's grains (`dem2d check --json`)."""
    cmd = [dem2d, "check", str(scene), "--initial", str(initial), "--json"]
    done = subprocess.run(cmd, capture_output=True, text=True)
    if done.returncode != 0:
        fail(f"{' '.join(cmd)} failed:\n{done.stderr}")
    return float(json.loads(done.stdout)["normal_damping_ratio"]["grains"])


def dem2d_scene(d: dict, settle: bool, steps: int = 0, dt: float = 0.0) -> str:
    """The dem2d scene: the settling pour, or the timed run on the settled bed."""
    bed, c = d["bed"], d["contact"]
    w, top = bed["cell_width"], bed["fill_height"]
    h = WALL / 2
    scene = {"name": f"bench_compare_{'settle' if settle else 'timed'}",
             "effects": {"gravity": True, "normal_damping": True, "friction": True, "walls": True},
             "gravity": {"g": [0.0, -bed["gravity"]]},
             "material": {"density": bed["density"]},
             "contact": {k: c[k] for k in ("kn", "kt", "restitution", "friction")},
             "neighbour": {"skin": c["skin"]}}
    if settle:
        s = d["settle"]
        scene["time"] = {"duration": s["duration"], "dt_over_critical": c["dt_over_critical"]}
        scene["stop"] = {"kinetic_energy_below": s["kinetic_energy_below"], "check_interval": 0.01,
                         "min_time": s["min_time"]}
        scene["output"] = {"series_interval": 0.01}
        scene["generator"] = [{"kind": "triangular_lattice", "count": bed["count"], "seed": bed["seed"],
                               "diameter": {"min": bed["diameter"][0], "max": bed["diameter"][1]},
                               "region": [[0.0, 0.0], [w, 0.0], [w, top], [0.0, top]]}]
    else:  # the settled bed comes from --initial; output only at the end
        duration = steps * dt
        scene["time"] = {"duration": duration, "dt": dt}
        scene["output"] = {"series_interval": duration, "snapshot_interval": duration}
    scene["domain"] = {"xmin": -0.01, "xmax": w + 0.01, "ymin": -0.01, "ymax": top + 0.2}
    scene["body"] = [{"name": "floor", "a": [-h, -h], "b": [w + h, -h], "thickness": WALL},
                     {"name": "left", "a": [-h, -h], "b": [-h, top + 0.2], "thickness": WALL},
                     {"name": "right", "a": [w + h, -h], "b": [w + h, top + 0.2], "thickness": WALL}]
    return tomlwrite.dumps(scene, "Written by pipeline/bench_compare/compare.py from data/bench/compare.toml: edit that.")


def final_state(run: Path) -> dict:
    """Positions, velocities, spins, diameters and grain-grain contacts at the end of a dem2d run."""
    with dem2d.open_run(run) as r:
        s = r.snapshot(-1)
        c = s.contacts
        return {"position": s.position, "velocity": s.velocity, "omega": s.omega,
                "diameter": r.particles.diameter, "dt": float(r.dt),
                "pair_contacts": int(np.count_nonzero(~c.is_body & (c.overlap > 0)))}


def lammps_inputs(d: dict, bed: dict, out: Path, steps: int, two_nu: float) -> Path:
    """The LAMMPS data file and input script for the timed run; returns the script."""
    c, w = d["contact"], d["bed"]["cell_width"]
    n = len(bed["diameter"])
    top = float(np.max(bed["position"][:, 1])) + 0.05
    lines = ["LAMMPS data file: the settled bed of pipeline/bench_compare/compare.py", "",
             f"{n} atoms", "1 atom types", "",
             f"-0.01 {w + 0.01} xlo xhi", f"-0.01 {top} ylo yhi", "-0.001 0.001 zlo zhi", "", "Atoms # sphere", ""]
    for i in range(n):
        x, y = bed["position"][i]
        lines.append(f"{i + 1} 1 {bed['diameter'][i]!r} {d['bed']['density']} {x!r} {y!r} 0.0")
    lines += ["", "Velocities", ""]
    for i in range(n):
        vx, vy = bed["velocity"][i]
        lines.append(f"{i + 1} {vx!r} {vy!r} 0.0 0.0 0.0 {bed['omega'][i]!r}")
    write_atomic(out / "bed.data", "\n".join(lines) + "\n")
    law = (f"hooke {c['kn']} {lammps_restitution(two_nu):.10f} "
           f"tangential linear_history {c['kt']} 0.0 {c['friction']} damping tsuji limit_damping")
    script = f"""# Written by pipeline/bench_compare/compare.py from data/bench/compare.toml: edit that.
units si
dimension 2
boundary f f p
atom_style sphere
atom_modify map array
comm_modify vel yes
newton off
read_data bed.data
set type 1 density/disc {d['bed']['density']}
pair_style granular
pair_coeff * * {law}
fix cell all wall/gran granular {law} xplane 0.0 {w}
fix floor all wall/gran granular {law} yplane 0.0 NULL
fix gravity all gravity {d['bed']['gravity']} vector 0 -1 0
fix step all nve/sphere disc
fix plane all enforce2d
neighbor {c['skin']} bin
neigh_modify delay 0 every 1 check yes
timestep {bed['dt']!r}
compute contacts all contact/atom
compute mean_contacts all reduce ave c_contacts
compute height all reduce ave y
thermo_style custom step c_mean_contacts c_height
thermo {steps}
run {steps}
"""
    write_atomic(out / "in.bench", script)
    return out / "in.bench"


def run_dem2d(dem2d: str, scene: Path, initial: Path, out: Path, cores: int) -> dict:
    cmd = [dem2d, "run", str(scene), "--initial", str(initial), "--out", str(out), "--threads", str(cores), "--fresh",
           "--overwrite"]  # timed afresh each time
    done = subprocess.run(cmd, capture_output=True, text=True)
    if done.returncode != 0:
        fail(f"{' '.join(cmd)} failed:\n{done.stderr}")
    ns = float(re.search(r"\(([0-9.eE+-]+) ns per particle-step", done.stderr).group(1))
    state = final_state(out / "run.h5")
    n = len(state["diameter"])
    return {"ns_per_particle_step": ns, "contact_number": 2.0 * state["pair_contacts"] / n,
            "bed_height_m": float(np.mean(state["position"][:, 1]))}


def run_lammps(script: Path, cores: int, steps: int) -> dict:
    mpi = ["mpirun", "-np", str(cores)] + (["--allow-run-as-root"] if os.geteuid() == 0 else [])
    cmd = mpi + ["lmp", "-in", script.name, "-log", f"log.{cores}", "-screen", "none"]
    done = subprocess.run(cmd, capture_output=True, text=True, cwd=script.parent)
    log = (script.parent / f"log.{cores}").read_text() if (script.parent / f"log.{cores}").exists() else ""
    if done.returncode != 0:
        fail(f"{' '.join(cmd)} (in {script.parent}) failed:\n{done.stderr}\n{log[-2000:]}")
    loop = re.search(r"Loop time of ([0-9.eE+-]+) on (\d+) procs for (\d+) steps with (\d+) atoms", log)
    seconds, atoms = float(loop.group(1)), int(loop.group(4))
    last = re.search(rf"^\s*{steps}\s+(\S+)\s+(\S+)\s*$", log, re.MULTILINE)
    return {"ns_per_particle_step": seconds * 1e9 / (steps * atoms), "contact_number": float(last.group(1)),
            "bed_height_m": float(last.group(2))}


def main() -> None:
    if len(sys.argv) != 4:
        fail(__doc__.split("\n\n")[1])
    description, dem2d, out = Path(sys.argv[1]), sys.argv[2], Path(sys.argv[3])
    d = read_toml(description)
    if shutil.which("lmp") is None or shutil.which("mpirun") is None:
        fail("LAMMPS (lmp) or mpirun not found: install the Debian package lammps (make bench-compare does)")
    steps = int(d["timing"]["steps"])
    out.mkdir(parents=True, exist_ok=True)

    settle_scene = out / "settle.toml"
    write_atomic(settle_scene, dem2d_scene(d, settle=True))
    settled = out / "settle" / "run.h5"
    t0 = time.time()  # settled afresh each time: seconds, and never stale
    done = subprocess.run([dem2d, "run", str(settle_scene), "--out", str(out / "settle"), "--fresh",
                           "--overwrite"],
                          capture_output=True, text=True)
    if done.returncode != 0:
        fail(f"settling the bed failed:\n{done.stderr}")
    print(f"settled the bed with dem2d in {time.time() - t0:.0f} s")
    bed = final_state(settled)
    timed_scene = out / "timed.toml"
    write_atomic(timed_scene, dem2d_scene(d, settle=False, steps=steps, dt=bed["dt"]))
    two_nu = 2.0 * dem2d_damping_ratio(dem2d, timed_scene, settled)
    script = lammps_inputs(d, bed, out, steps, two_nu)

    rows = []
    for cores in d["timing"]["cores"]:
        ours = run_dem2d(dem2d, timed_scene, settled, out / f"dem2d_{cores}", cores)
        theirs = run_lammps(script, cores, steps)
        rows.append({"cores": cores, "dem2d": ours, "lammps": theirs,
                     "speed_ratio": theirs["ns_per_particle_step"] / ours["ns_per_particle_step"]})
        print(f"  {cores} core(s): dem2d {ours['ns_per_particle_step']:.1f} ns/particle-step, "
              f"LAMMPS {theirs['ns_per_particle_step']:.1f}: {rows[-1]['speed_ratio']:.1f}x", flush=True)

    tol = d["agreement"]
    agree = True
    for r in rows:
        for key, name in (("contact_number", "contact_number"), ("bed_height_m", "bed_height")):
            a, b = r["dem2d"][key], r["lammps"][key]
            r[f"{key}_rel_diff"] = abs(a - b) / abs(b)
            agree &= r[f"{key}_rel_diff"] <= tol[name]
    one = {r["cores"]: r for r in rows}
    result = {"description": str(description), "particles": len(bed["diameter"]), "steps": steps,
              "dt_s": bed["dt"], "lammps_restitution": lammps_restitution(two_nu),
              "rows": rows, "agree": agree}
    if 1 in one and 2 in one:
        result["dem2d_two_core_speedup"] = (one[1]["dem2d"]["ns_per_particle_step"] /
                                            one[2]["dem2d"]["ns_per_particle_step"])
        result["lammps_two_core_speedup"] = (one[1]["lammps"]["ns_per_particle_step"] /
                                             one[2]["lammps"]["ns_per_particle_step"])
    write_atomic(out / "compare.json", json.dumps(result, indent=2) + "\n")

    md = ["| cores | dem2d ns/particle-step | LAMMPS ns/particle-step | LAMMPS/dem2d | contacts per grain "
          "dem2d / LAMMPS | mean height (mm) dem2d / LAMMPS |", "|---|---|---|---|---|---|"]
    for r in rows:
        md.append(f"| {r['cores']} | {r['dem2d']['ns_per_particle_step']:.1f} | "
                  f"{r['lammps']['ns_per_particle_step']:.1f} | {r['speed_ratio']:.1f}x | "
                  f"{r['dem2d']['contact_number']:.3f} / {r['lammps']['contact_number']:.3f} | "
                  f"{1e3 * r['dem2d']['bed_height_m']:.2f} / {1e3 * r['lammps']['bed_height_m']:.2f} |")
    write_atomic(out / "compare.md", "\n".join(md) + "\n")
    print("\n".join(md))
    if not agree:
        fail(f"the two codes' runs disagree beyond {tol}: not equal work (see {out / 'compare.json'})")


if __name__ == "__main__":
    main()
