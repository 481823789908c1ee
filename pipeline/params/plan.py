"""make params' plan: from data/params.toml, every point's scenes and overlay,
and the make rules that run its members and aggregate them
(RESULTS/plan.mk, included by the Makefile for `make params`).

    /usr/bin/python3 -m pipeline.params.plan data/params.toml PLAN RESULTS_DIR

PLAN is a table of data/params.toml ([reduced], [full], ...): the preset,
the pull speed, the members, the bed. A point changes one knob of the base
point (docs/params.md):

  cell_width_mm            the cell's width L_c: walls, floor, intruder centred, hopper and
                           domain moved with it, the grain count scaled to keep the bed height
  intruder_length_mm       the intruder's length L, tip to tip
  intruder_shape           "segment" (the paper's sphero-line, docs/paper.md) or "square" (square ends)
  pull_speed_mm_s          V: every pull-off time given in travel scales with 1/V; the point
                           starts from the base point's beds (only the pull changes)
  friction                 mu of grains and walls
  rolling_friction_over_r  mu_r / r of a mean grain (docs/paper.md: mu d 1e-2 / (d/2) = 0.01)
  bond_number              cohesion: pull-off force f_c = Bo m g of a mean grain, range 0.05 d
  cycles                   cyclic loading (pipeline/cyclic.toml) from the base point's beds:
                           the rise, a rest, then this many up-and-down cycles, at the plan's speed

The scenes (fill.toml, pulloff.toml: the bed and the pull with the point's
geometry and speed) are whole scenes; the contact-law knobs are an overlay
applied after the preset (overlay.toml). Member k of a point is the study with
the fill's grain seeds moved by k (pipeline/ensemble/member_overlay.py).
Files are rewritten only when their content changes: make reruns only what a
changed setting touches.
"""
import json
import math
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
from pipeline import tomlwrite
from pipeline.pull_speed import speed_overlay
from pipeline.files import fail, read_toml, write_if_changed

FILLS = {"settle": Path("pipeline/params/fill_settle.toml"), "hopper": Path("pipeline/fill.toml")}
PULLOFF = Path("pipeline/pulloff.toml")
CYCLIC = Path("pipeline/cyclic.toml")
SQUARE = Path("pipeline/intruders/square.toml")
BASE_CELL_MM, BASE_LENGTH_MM = 100.0, 10.0
KNOBS = {"cell_width_mm": float, "intruder_length_mm": float, "intruder_shape": str, "pull_speed_mm_s": float,
         "friction": float, "rolling_friction_over_r": float, "bond_number": float, "cycles": int}
PLAN_KEYS = {"preset", "pull_speed_mm_s", "members", "base_members", "fill", "threads", "sweeps"}
SWEEP_KEYS = {"name", "knob", "values", "claims"}
G = 9.81  # m/s^2, as the scenes' gravity
# The cost model of the plan's estimate: single-thread ns per particle-step measured on this machine's
# pull-offs (preset fast: 36 ns with two runs side by side, 17 ns alone; docs/params.md), and the
# analyses' time per run (cg ~70 s of the ~100 s)
NS_PER_PARTICLE_STEP = 25.0
ANALYSIS_S = 100.0
SETTLE_S = 1.0     # simulated seconds a settled bed takes (0.6 s measured on the base)
HOPPER_S = 20.0    # simulated seconds the hopper's pour takes (the fast ensemble's fills: 19.98 s)
# A Slurm task's time limit (--time): this many times its estimate, and at least MIN_TASK_MINUTES, so that a
# task on a lost node ends (and is requeued) instead of holding the study forever (docs/ensemble.md)
TIME_LIMIT_FACTOR = 3.0
MIN_TASK_MINUTES = 10


def task_minutes(seconds: float) -> int:
    """The --time limit (minutes) of a Slurm task estimated to take `seconds` on one core."""
    return max(MIN_TASK_MINUTES, math.ceil(TIME_LIMIT_FACTOR * seconds / 60))


def mean_grain(scene: dict) -> tuple[float, float]:
    """Mean diameter (m) and mass per unit depth (kg/m) of the scene's generated grains."""
    d = scene["generator"][0]["diameter"]
    mean = 0.5 * (d["min"] + d["max"])
    return mean, scene["material"]["density"] * math.pi * mean ** 2 / 4


def bodies(scene: dict) -> dict:
    return {b["name"]: b for b in scene["body"]}


def shift_x(points, dx):
    return [[x + dx, y] for x, y in points]


def geometry(scene: dict, cell_mm: float, length_mm: float, shape: str, fill: bool) -> dict:
    """The scene with the cell L_c wide (inner faces x = 0 and L_c), the intruder L long and centred,
    what sits above the cell (hopper, generator region, domain) moved with its centre; in a fill the
    grain count scales with L_c (the same bed height) and the region grows to hold them."""
    s = {k: (v.copy() if isinstance(v, dict) else v) for k, v in scene.items()}
    s["body"] = [dict(b) for b in scene["body"]]
    w, old_w = cell_mm * 1e-3, BASE_CELL_MM * 1e-3
    dx = (w - old_w) / 2  # the cell's centre moves by this
    by = bodies(s)
    right, floor, intruder = by["right"], by["floor"], by["intruder"]
    right["a"], right["b"] = [w + 0.001, right["a"][1]], [w + 0.001, right["b"][1]]
    floor["b"] = [w + 0.001, floor["b"][1]]
    t = intruder["thickness"]
    centre, y = w / 2, intruder["a"][1]
    if shape == "square":
        square = bodies(read_toml(SQUARE))["intruder"]
        for key in ("a", "b"):
            intruder.pop(key)
        intruder.update(shape="rectangle", centre=[centre, square["centre"][1]], size=[length_mm * 1e-3, square["size"][1]],
                        thickness=square["thickness"])
    else:
        half = (length_mm * 1e-3 - t) / 2  # a sphero-line's core: L less its caps
        intruder["a"], intruder["b"] = [centre - half, y], [centre + half, y]
    hopper = [b for b in s["body"] if b.get("role") == "hopper"]
    for b in hopper:
        b["a"], b["b"] = [b["a"][0] + dx, b["a"][1]], [b["b"][0] + dx, b["b"][1]]
    if hopper and dx < 0:
        # the hopper is wider than a narrower cell: its walls end below the funnel
        outlet = min(min(b["a"][1], b["b"][1]) for b in hopper)
        for wall in (by["left"], by["right"]):
            wall["b"] = [wall["b"][0], min(wall["b"][1], outlet)]
    s["domain"] = dict(s["domain"], xmin=s["domain"]["xmin"] + min(dx, 0.0), xmax=s["domain"]["xmax"] + max(2 * dx, 0.0))
    if fill:
        g = dict(s["generator"][0])
        n = g["count"]
        g["count"] = round(n * cell_mm / BASE_CELL_MM)
        region = shift_x(g["region"], dx)
        if any(b.get("role") == "hopper" for b in s["body"]):
            # the hopper's silo keeps its width: its column of grains grows with their number
            top = max(y for _, y in region)
            bottom = min(y for x, y in region if y > min(yy for _, yy in region))
            new_top = bottom + (top - bottom) * g["count"] / n
            region = [[x, new_top if yy == top else yy] for x, yy in region]
            s["domain"]["ymax"] = max(s["domain"]["ymax"], new_top + 0.02)
        else:
            # a settled bed: the region is the cell (as many rows: the count scales with the width)
            region = [[x * w / old_w, y] for x, y in g["region"]]
        g["region"] = region
        s["generator"] = [g]
    return s


def speed(scene: dict, v_mm_s: float) -> dict:
    """The pull-off at V (pipeline/pull_speed.py), merged into the scene."""
    over = speed_overlay(scene, v_mm_s * 1e-3)
    s = {k: (dict(v, **over[k]) if k in over and k != "body" else v) for k, v in scene.items()}
    s["body"] = [dict(b, **over["body"][0]) if b["name"] == "intruder" else b for b in scene["body"]]
    return s


def cyclic(scene: dict, v_mm_s: float, cycles: int) -> dict:
    """The cyclic scene at V (its constant rise and triangles at V, the rests as they are) with `cycles` cycles;
    the duration follows, the output intervals scale with 1/V."""
    s = {k: (dict(v) if isinstance(v, dict) else v) for k, v in scene.items()}
    s["body"] = [dict(b) for b in scene["body"]]
    intruder = bodies(s)["intruder"]
    rise = next(m for m in intruder["motion"] if m["kind"] == "constant")
    f = rise["velocity"][1] / (v_mm_s * 1e-3)  # old speed / new
    motion = []
    for m in intruder["motion"]:
        m = dict(m)
        if m["kind"] == "constant":
            m["velocity"], m["duration"] = [0.0, v_mm_s * 1e-3], m["duration"] * f
        elif m["kind"] == "triangle":
            m["period"], m["cycles"] = m["period"] * f, cycles
        motion.append(m)
    intruder["motion"] = motion
    spans = [m["duration"] if "duration" in m else m["period"] * m.get("cycles", 1) for m in motion]
    s["time"]["duration"] = sum(spans) + 2.0  # s: and 2 s at rest after the last cycle
    for key in ("series_interval", "snapshot_interval", "displacement_window"):
        if key in s["output"]:
            s["output"][key] = scene["output"][key] * f
    return s


def time_step(fill: dict, preset: dict) -> float:
    """The run's time step (s): dt_over_critical x dt_c, dt_c = sqrt(m_min / k_n) for the smallest grain (or dt)."""
    if "dt" in preset["time"]:
        return preset["time"]["dt"]
    d_min = fill["generator"][0]["diameter"]["min"]
    m_min = fill["material"]["density"] * math.pi * d_min ** 2 / 4
    return preset["time"]["dt_over_critical"] * math.sqrt(m_min / preset["contact"]["kn"])


def run_cost(fill: dict, pull: dict, cyclic_scene, settings: dict, plan: dict, preset: dict, own_bed: bool) -> float:
    """Estimated single-core seconds of one member: its bed (unless shared), the pull-off (its travel: the bed
    and 10 mm more at V, then the free time) or the cyclic run, and the analyses."""
    dt, n = time_step(fill, preset), fill["generator"][0]["count"]
    bed = (HOPPER_S if plan["fill"] == "hopper" else SETTLE_S) if own_bed else 0.0
    v = settings["pull_speed_mm_s"] * 1e-3
    run = cyclic_scene["time"]["duration"] if cyclic_scene else 0.16 / v + pull["stop"]["free_time"]
    return n * (bed + run) / dt * NS_PER_PARTICLE_STEP * 1e-9 + ANALYSIS_S


def law(knob: str, value, fill: dict, preset: dict) -> dict:
    """The overlay of a contact-law knob (after the preset)."""
    d, m = mean_grain(fill)
    if knob == "friction":
        return {"contact": {"friction": value, "wall": {"friction": value}}}
    if knob == "rolling_friction_over_r":
        return {"contact": {"rolling_friction": value * d / 2}}
    if knob == "bond_number":
        if value == 0:
            return {}
        return {"effects": {"cohesion": True},
                "contact": {"cohesion_force": value * m * G, "cohesion_range": 0.05 * d}}
    return {}


def check(config: dict, plan_name: str, where: Path) -> tuple[dict, list]:
    if plan_name not in config or plan_name == "sweep":
        fail(f"{where}: no plan [{plan_name}] (plans: {', '.join(k for k in config if k != 'sweep')})")
    plan = config[plan_name]
    unknown = set(plan) - PLAN_KEYS
    if unknown:
        fail(f"{where}: [{plan_name}]: unknown keys {sorted(unknown)} (allowed: {sorted(PLAN_KEYS)})")
    if not Path(f"pipeline/presets/{plan.get('preset')}.toml").exists():
        fail(f"{where}: [{plan_name}] preset = {plan.get('preset')!r}: no pipeline/presets/<preset>.toml")
    if plan.get("fill") not in FILLS:
        fail(f"{where}: [{plan_name}] fill = {plan.get('fill')!r}: allowed {sorted(FILLS)}")
    for key in ("members", "base_members"):
        if not isinstance(plan.get(key), int) or not 1 <= plan[key] <= 100:
            fail(f"{where}: [{plan_name}] {key} = {plan.get(key)!r}: an integer from 1 to 100")
    if not isinstance(plan.get("pull_speed_mm_s"), (int, float)) or not 0.1 <= plan["pull_speed_mm_s"] <= 100:
        fail(f"{where}: [{plan_name}] pull_speed_mm_s = {plan.get('pull_speed_mm_s')!r}: from 0.1 to 100 mm/s")
    sweeps = config.get("sweep", [])
    if "sweeps" in plan:  # the plan runs only these
        known = {s.get("name") for s in sweeps}
        if not isinstance(plan["sweeps"], list) or not set(plan["sweeps"]) <= known:
            fail(f"{where}: [{plan_name}] sweeps = {plan['sweeps']!r}: names of [[sweep]]s ({', '.join(sorted(known))})")
        sweeps = [s for s in sweeps if s["name"] in plan["sweeps"]]
    names = set()
    for i, s in enumerate(sweeps):
        at = f"{where}: sweep[{i}]"
        if set(s) - SWEEP_KEYS or not {"name", "knob", "values"} <= set(s):
            fail(f"{at}: needs name, knob, values (and optionally claims); unknown keys {sorted(set(s) - SWEEP_KEYS)}")
        if s["knob"] not in KNOBS:
            fail(f"{at} ({s['name']}): knob = {s['knob']!r}: allowed {sorted(KNOBS)}")
        if s["name"] in names:
            fail(f"{at}: name {s['name']!r} is used twice")
        names.add(s["name"])
        kind = KNOBS[s["knob"]]
        for v in s["values"]:
            if kind is str:
                ok, allowed = v in ("segment", "square"), "segment or square"
            elif kind is int:
                ok, allowed = isinstance(v, int) and 1 <= v <= 100, "an integer from 1 to 100"
            else:
                ok, allowed = isinstance(v, (int, float)) and math.isfinite(v) and v >= 0, "a number >= 0"
            if not ok:
                fail(f"{at} ({s['name']}): value {v!r}: {allowed}")
    return plan, sweeps


def main() -> None:
    if len(sys.argv) != 4:
        fail("usage: python3 -m pipeline.params.plan data/params.toml PLAN RESULTS_DIR")
    config_path, plan_name, out = Path(sys.argv[1]), sys.argv[2], Path(sys.argv[3])
    config = read_toml(config_path)
    plan, sweeps = check(config, plan_name, config_path)
    preset = read_toml(Path(f"pipeline/presets/{plan['preset']}.toml"))
    fill0, pull0 = read_toml(FILLS[plan["fill"]]), read_toml(PULLOFF)
    base = {"cell_width_mm": BASE_CELL_MM, "intruder_length_mm": BASE_LENGTH_MM, "intruder_shape": "segment",
            "pull_speed_mm_s": float(plan["pull_speed_mm_s"]), "friction": preset["contact"]["friction"],
            "rolling_friction_over_r": preset["contact"]["rolling_friction"] / (mean_grain(fill0)[0] / 2),
            "bond_number": 0.0, "cycles": 0}
    points = [("base", "base", None, base)]
    for s in sweeps:
        for v in s["values"]:
            if v == base[s["knob"]]:
                continue  # the base point itself
            label = v if isinstance(v, str) else f"{v:g}"
            points.append((f"{s['name']}_{label}", s["name"], s["knob"], dict(base, **{s["knob"]: v})))
    threads = plan.get("threads", 1)
    rules, stats, index, waves = [], [], [], []
    cost = 0.0
    for name, sweep, knob, settings in points:
        d = out / "points" / name
        fill = geometry(fill0, settings["cell_width_mm"], settings["intruder_length_mm"], settings["intruder_shape"], True)
        pull = speed(geometry(pull0, settings["cell_width_mm"], settings["intruder_length_mm"],
                              settings["intruder_shape"], False), settings["pull_speed_mm_s"])
        fill["name"], pull["name"] = f"fill_{name}", f"pulloff_{name}"
        head = f"make params point {name} ({plan_name}): written by pipeline/params/plan.py from {config_path}"
        write_if_changed(d / "fill.toml", tomlwrite.dumps(fill, head))
        write_if_changed(d / "pulloff.toml", tomlwrite.dumps(pull, head))
        overlay = {}
        for k in ("friction", "rolling_friction_over_r", "bond_number"):
            if knob == k:
                overlay = law(k, settings[k], fill, preset)
        write_if_changed(d / "overlay.toml", tomlwrite.dumps(overlay, head + "\nthe contact-law knob, after the preset"))
        cyc = knob == "cycles"
        cyclic_scene = cyclic(read_toml(CYCLIC), settings["pull_speed_mm_s"], settings["cycles"]) if cyc else None
        if cyc:
            write_if_changed(d / "cyclic.toml", tomlwrite.dumps(dict(cyclic_scene, name=f"cyclic_{name}"), head))
        shared_bed = knob in ("pull_speed_mm_s", "cycles")  # only the pull changes: the base point's beds
        members = plan["base_members"] if name == "base" else plan["members"]
        member_cost = run_cost(fill, pull, cyclic_scene, settings, plan, preset, not shared_bed)
        cost += members * member_cost
        member_dirs = []
        for k in range(members):
            m = d / f"member_{k:03d}"
            seeds = m / "seeds.toml"
            fill_run = out / "points" / "base" / f"member_{k:03d}" / "fill" / "run.h5" if shared_bed else m / "fill" / "run.h5"
            rules.append(f"{seeds}: {d}/fill.toml pipeline/ensemble/member_overlay.py\n"
                         f"\t$(PYTHON) -m pipeline.ensemble.member_overlay {d}/fill.toml {k} $@\n")
            # a member: the study's own make targets (`metrics`; `cyclic` for cyclic loading) in its folder
            goal, target = ("cyclic", f"{m}/cyclic/metrics.json") if cyc else ("metrics", f"{m}/metrics.json")
            rules.append(f"{target}: {d}/fill.toml {d}/pulloff.toml {d}/overlay.toml {seeds}"
                         f"{' ' + str(d / 'cyclic.toml') if cyc else ''}{' ' + str(fill_run) if shared_bed else ''} FORCE\n"
                         f"\t+@$(MAKE) --no-print-directory {goal} PRESET={plan['preset']} RESULTS={m} "
                         f"FILL_SCENE={d}/fill.toml PULLOFF_SCENE={d}/pulloff.toml POINT_OVERLAY={d}/overlay.toml "
                         f"{f'CYCLIC_SCENE={d}/cyclic.toml ' if cyc else ''}"
                         f"FILL_OVERLAY={seeds} FILL_RUN={fill_run} THREADS={threads}\n")
            if shared_bed:
                rules.append(f"{fill_run}: {out / 'points' / 'base' / f'member_{k:03d}' / 'metrics.json'}\n")
            member_dirs.append(str(m))
            waves.append(f"{2 if shared_bed else 1} {target} {task_minutes(member_cost)}")  # Slurm: shared beds first
        if cyc:  # read by the report itself (drag per cycle, the bed between cycles)
            stats += [f"{m}/cyclic/metrics.json" for m in member_dirs]
        else:
            rules.append(f"{d}/stats.json: {' '.join(m + '/metrics.json' for m in member_dirs)} pipeline/ensemble/aggregate.py\n"
                         f"\t$(PYTHON) -m pipeline.ensemble.aggregate {d} {plan['preset']} {' '.join(member_dirs)}\n")
            stats.append(f"{d}/stats.json")
        index.append({"point": name, "sweep": sweep, "knob": knob, "settings": settings, "members": member_dirs,
                      "shared_bed": shared_bed})
    write_if_changed(out / "plan.json", json.dumps(
        {"plan": plan_name, **plan, "base": base, "estimated_core_hours": round(cost / 3600, 2), "points": index},
        indent=1) + "\n")
    runs = sum(len(p["members"]) for p in index)
    print(f"params plan {plan_name}: {len(index)} points, {runs} runs, about {cost / 3600:.1f} h on one core "
          f"({cost / 3600 / 2:.1f} h on 2 cores side by side) -> {out}/plan.mk", file=sys.stderr)
    write_if_changed(out / "targets.txt", "\n".join(waves) + "\n")
    text = (f"# Written by pipeline/params/plan.py from {config_path} (plan {plan_name}): make params' rules.\n"
            f"PARAMS_STATS := {' '.join(stats)}\n\n" + "\n".join(rules))
    write_if_changed(out / "plan.mk", text)


if __name__ == "__main__":
    main()
