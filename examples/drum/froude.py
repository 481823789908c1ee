"""The drum of examples/drum/scene.toml at several Froude numbers Fr = omega^2 R / g:
one run each (an overlay setting every wall's angular velocity and the run's
duration), its dynamic angle of repose and torque measured as plot.py does;
a table (stdout, OUT/froude.csv) and the angle against Fr (OUT/froude.png).

    python3 examples/drum/froude.py DEM2D OUT [--froude 0.001 0.01 0.1] [--turn 4.5] [--settle 1.5]

DEM2D is the engine's program (build/release/sim/dem2d). Each run turns the
drum `--turn` rad after its spin-up; the first `--settle` rad are left out as
the bed's transient.
"""
import argparse
import csv
import math
import os
import subprocess
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "python"))
sys.path.insert(0, HERE)
import dem2d  # noqa: E402
from plot import measure  # noqa: E402

SCENE = os.path.join(HERE, "scene.toml")
RADIUS, G, WALLS = 0.04, 9.81, 16  # the scene's drum (m), gravity (m/s^2), its walls drum_00 ...
SPIN_UP = 0.6                       # s: the scene's hold (0.4 s) and ramp (0.2 s)


def overlay(froude, turn):
    """The overlay that turns the scene's drum at `froude` for `turn` rad after its spin-up."""
    omega = math.sqrt(froude * G / RADIUS)
    text = (f"[time]\nduration = {SPIN_UP + 0.1 + turn / omega!r}  # s\n\n"
            f"[output]\nsnapshot_interval = {0.05 / omega!r}  # s: every 0.05 rad\n")
    for k in range(WALLS):
        text += (f'\n[[body]]\nname = "drum_{k:02d}"\nmotion = [\n  {{ kind = "hold", duration = 0.4 }},\n'
                 f'  {{ kind = "ramp", angular_velocity = {omega!r}, duration = 0.2 }},\n'
                 f'  {{ kind = "constant", angular_velocity = {omega!r} }},\n]\n')
    return text


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("dem2d")
    ap.add_argument("out")
    ap.add_argument("--froude", type=float, nargs="+", default=[0.001, 0.01, 0.1])
    ap.add_argument("--turn", type=float, default=4.5, help="rad the drum turns after its spin-up")
    ap.add_argument("--settle", type=float, default=1.5, help="rad it turns before the bed counts as steady")
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    rows = []
    for fr in args.froude:
        folder = os.path.join(args.out, f"fr_{fr:g}")
        os.makedirs(folder, exist_ok=True)
        with open(os.path.join(folder, "froude.toml"), "w") as f:
            f.write(overlay(fr, args.turn))
        r = subprocess.run([args.dem2d, "run", SCENE, "--overlay", f.name, "--out", os.path.join(folder, "run"),
                            "--threads", "1", "--overwrite"], capture_output=True, text=True)
        if r.returncode != 0:
            sys.exit(f"froude: the run at Fr = {fr:g} failed (exit {r.returncode}): {r.stderr.strip()}")
        with dem2d.open_run(os.path.join(folder, "run", "run.h5")) as run:
            m = measure(run, args.settle)
            grains = run.n_particles
        a = m["angles"]
        rows.append(dict(froude=m["froude"], omega=m["omega"], angle_deg=a.mean(), angle_se_deg=m["angle_se"],
                         angle_sd_deg=a.std(),
                         snapshots=len(a), torque=m["torque"], gravity_torque=-m["gravity_torque"],
                         bed_omega=m["bed_omega"], spin=m["spin"]))
        print(f"Fr = {m['froude']:.4g} (omega {m['omega']:.4f} rad/s): dynamic angle of repose {a.mean():.2f} "
              f"+- {m['angle_se']:.2f} deg (sd {a.std():.2f}, {len(a)} snapshots); torque on the drum {m['torque']:.5f} N, "
              f"-g M x_com {-m['gravity_torque']:.5f} N; the bed turns at {m['bed_omega'] / m['omega']:.4f} omega, "
              f"its grains spin at {m['spin'] / m['omega']:.4f} omega", flush=True)
    with open(os.path.join(args.out, "froude.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    fig, ax = plt.subplots(figsize=(5, 4), constrained_layout=True)
    ax.errorbar([r["froude"] for r in rows], [r["angle_deg"] for r in rows],
                yerr=[2 * r["angle_se_deg"] for r in rows], fmt="o-", capsize=3)
    ax.set_xscale("log")
    ax.set_xlabel("Froude number ω²R/g")
    ax.set_ylabel("dynamic angle of repose (°)")
    ax.set_title(f"rotating drum, {grains} disks (bars: 2 standard errors)")
    fig.savefig(os.path.join(args.out, "froude.png"), dpi=120)


if __name__ == "__main__":
    main()
