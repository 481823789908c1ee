"""The accuracy sweep's plan: from data/accuracy.toml, every point's overlay,
every bed the points start from, every cg configuration, and the make rules
that run them (RESULTS/plan.mk, included by the Makefile for `make accuracy`).

    /usr/bin/python3 -m pipeline.accuracy.plan data/accuracy.toml results/accuracy

A point changes one knob of the base preset: the contact stiffness k_n (k_t
and k_r scale with it, the time step follows dt_c), dt / dt_c, or the pull
speed V (every time of the pull-off scene given in travel scales with 1/V).
A replica (knob "replica") is the point it names (`replica_of`) with a time
step slightly changed: the same setting, another trajectory.
A point with another k_n starts from the default fill re-settled under that
k_n, at most a factor of 10 at a time (pipeline/accuracy/resettle.toml).

Files are rewritten only when their content changes, so make reruns only the
points whose settings changed.
"""
import math
import sys
from pathlib import Path

from pipeline import stages
from pipeline import tomlwrite
from pipeline.accuracy.table import reference_members
from pipeline.pull_speed import intruder_speed, speed_overlay
from pipeline.files import fail, read_toml, write_if_changed

PULLOFF_SCENE = Path("pipeline/pulloff.toml")
RESETTLE_SCENE = Path("pipeline/accuracy/resettle.toml")
KNOBS = {"reference": [], "default": [], "replica": ["dt_over_critical"], "kn": ["kn"], "dt": ["dt_over_critical"],
         "V": ["V_mm_s"]}
POINT_KEYS = {"name", "knob", "preset", "extent", "full_reference", "kn", "dt_over_critical", "V_mm_s", "replica_of"}
CG_KEYS = {"name", "spacing_mm", "w_over_d", "reference"}


def toml_text(header: str, tables: dict) -> str:
    """tables: {"contact": {...}, "body": [{...}]}."""
    return tomlwrite.dumps(tables, f"{header}\nWritten by pipeline/accuracy/plan.py from data/accuracy.toml: edit that, not this.")


def stiffness(kn: float, preset: dict) -> dict:
    """[contact] for k_n, with k_t and k_r in the preset's ratios to its k_n."""
    c = preset["contact"]
    return {"kn": kn, "kt": kn * c["kt"] / c["kn"], "rolling_stiffness": kn * c["rolling_stiffness"] / c["kn"]}


def check_point(p: dict, where: str) -> None:
    if "name" not in p:
        fail(f"{where}: no name")
    unknown = set(p) - POINT_KEYS
    if unknown:
        fail(f"{where} ({p['name']}): unknown keys {sorted(unknown)}; allowed: {sorted(POINT_KEYS)}")
    if p.get("knob") not in KNOBS:
        fail(f"{where} ({p['name']}): knob = {p.get('knob')!r}: must be one of {list(KNOBS)}")
    if p.get("extent") not in ("full", "slice"):
        fail(f"{where} ({p['name']}): extent = {p.get('extent')!r}: must be \"full\" or \"slice\"")
    for key in KNOBS[p["knob"]]:
        if not isinstance(p.get(key), (int, float)) or p[key] <= 0:
            fail(f"{where} ({p['name']}): {key} = {p.get(key)!r}: must be a number > 0")
    if (p["knob"] == "replica") != ("replica_of" in p):
        fail(f"{where} ({p['name']}): replica_of is given for knob = \"replica\" (the name of the point it replicates), "
             f"and only for it")
    extra = set(p) & {"kn", "dt_over_critical", "V_mm_s"} - set(KNOBS[p["knob"]])
    if extra:
        fail(f"{where} ({p['name']}): {sorted(extra)} not used by knob = {p['knob']!r} (it uses {KNOBS[p['knob']]})")


def replicated(p: dict, points: list, where: str) -> dict:
    """A replica: the point it names (not itself a replica, with the same extent), its time step changed."""
    original = next((q for q in points if q["name"] == p["replica_of"]), None)
    if original is None or original["knob"] == "replica" or original["extent"] != p["extent"]:
        fail(f"{where} ({p['name']}): replica_of = {p['replica_of']!r}: must name another point of the same extent "
             f"that is not a replica; points: {[q['name'] for q in points]}")
    return {**original, "name": p["name"], "knob": "replica", "dt_over_critical": p["dt_over_critical"],
            "full_reference": False, "replica_of": p["replica_of"]}


def point_overlay(p: dict, preset: dict, pulloff: dict, slice_mm: float) -> dict:
    """p: a point, a replica already merged with the point it replicates (its kn, V, preset)."""
    tables: dict = {}
    speed = intruder_speed(pulloff)
    if "kn" in p:
        tables["contact"] = stiffness(p["kn"], preset)
    if "dt_over_critical" in p:
        tables["time"] = {"dt_over_critical": p["dt_over_critical"]}
    if "V_mm_s" in p:
        speed = p["V_mm_s"] * 1e-3
        tables.update(speed_overlay(pulloff, speed))
    if p["extent"] == "slice":
        tables.setdefault("time", {})["duration"] = slice_mm * 1e-3 / speed
    return tables


def kn_label(kn: float) -> str:
    return f"{kn:.2e}".replace("e+0", "e").replace("e+", "e")


def main() -> None:
    if len(sys.argv) != 3:
        fail("usage: python3 -m pipeline.accuracy.plan data/accuracy.toml RESULTS_DIR")
    config_path, out = Path(sys.argv[1]), Path(sys.argv[2])
    config = read_toml(config_path)
    sweep = config.get("sweep", {})
    base = sweep.get("base_preset", "default")
    presets = {}

    def preset(name: str) -> dict:
        if name not in presets:
            path = Path(f"pipeline/presets/{name}.toml")
            if not path.exists():
                fail(f"{config_path}: preset = {name!r}: there is no {path}")
            presets[name] = read_toml(path)
        return presets[name]

    pulloff = read_toml(PULLOFF_SCENE)
    base_kn = preset(base)["contact"]["kn"]
    base_bed = f"results/{base}/fill/run.h5"
    slice_mm = sweep.get("slice_mm", 10.0)
    threads = sweep.get("threads", 1)
    rules, beds, targets, reference_targets = [], {}, [], []
    # the base preset's fill, by its own rules when make runs for another preset
    rules.append(f"ifneq ($(PRESET),{base})\n{base_bed}: FORCE\n"
                 f"\t+@$(MAKE) --no-print-directory {base_bed} PRESET={base}\nendif\n")

    def bed(kn: float) -> str:
        """Run file of the default fill re-settled at k_n: factors of 10 from the base's k_n, the last step
        whatever is left (1.92e6 -> 6.07e6: one step of 3.16)."""
        decades = math.log10(kn / base_kn)
        steps = math.ceil(abs(decades) - 1e-6)
        path = base_bed
        for i in range(1, steps + 1):
            k = kn if i == steps else base_kn * 10.0 ** math.copysign(i, decades)
            d = out / "beds" / f"kn_{kn_label(k)}"
            if k not in beds:
                overlay = d / "overlay.toml"
                write_if_changed(overlay, toml_text(f"bed re-settled at k_n = {k:g} N/m", {"contact": stiffness(k, preset(base))}))
                rules.append(f"{d}/run.h5: {path} {overlay} {RESETTLE_SCENE} $(DEM2D)\n"
                             f"\t$(DEM2D) run {RESETTLE_SCENE} --overlay pipeline/presets/{base}.toml --overlay {overlay} "
                             f"--initial {path} --out $(@D) --threads {threads} --overwrite\n")
                beds[k] = f"{d}/run.h5"
            path = beds[k]
        return path

    points = config.get("point", [])
    reference = reference_members(points)  # the whole-run reference and its replicas
    names = set()
    for i, p in enumerate(points):
        check_point(p, f"{config_path}: point[{i}]")
        if p["name"] in names:
            fail(f"{config_path}: point[{i}]: name {p['name']!r} is used twice")
        names.add(p["name"])
        if p["knob"] == "replica":
            p = replicated(p, points, f"{config_path}: point[{i}]")
        name_preset = p.get("preset", base)
        pre = preset(name_preset)
        kn = p.get("kn", pre["contact"]["kn"])
        d = out / "points" / p["name"]
        overlay = d / "overlay.toml"
        write_if_changed(overlay, toml_text(f"accuracy point {p['name']}: {p['knob']}, {p['extent']}",
                                            point_overlay(p, pre, pulloff, slice_mm)))
        goal, target = ("metrics", d / "metrics.json") if p["extent"] == "full" else ("pulloff", d / "pulloff/metrics.json")
        fill_run = bed(kn)
        rules.append(f"{target}: {fill_run} {overlay} FORCE\n"
                     f"\t+@$(MAKE) --no-print-directory {goal} PRESET={name_preset} RESULTS={d} POINT_OVERLAY={overlay} "
                     f"FILL_RUN={fill_run} THREADS={threads}\n")
        targets.append(str(target))
        if p["name"] in reference:
            reference_targets.append(str(target))

    default_point = next((p for p in points if p["knob"] == "default" and p["extent"] == "full"), None)
    # the cg stage's command line as the registry gives it (its inputs from the point's own outputs)
    cg = next(s for s in stages.load() if s.name == "cg")
    for i, c in enumerate(config.get("cg", [])):
        unknown = set(c) - CG_KEYS
        if unknown or "name" not in c:
            fail(f"{config_path}: cg[{i}]: needs name, spacing_mm, w_over_d; unknown keys {sorted(unknown)}")
        if default_point is None:
            fail(f"{config_path}: [[cg]] points need a point with knob = \"default\" and extent = \"full\"")
        run_dir = out / "points" / default_point["name"]
        d = out / "cg" / c["name"]
        cfg = d / "cg.toml"
        write_if_changed(cfg, toml_text(f"cg setting {c['name']} (over data/cg.toml's defaults)",
                                        {"kernel": {"w_over_d": c["w_over_d"]}, "grid": {"spacing_mm": c["spacing_mm"]},
                                         "output": {"field_every_mm": 0.0, "field_max_snapshots": 1}}))
        inputs = "".join(f" {flag} {run_dir}/{source}" for flag, source in cg.inputs.items())
        rules.append(f"{d}/metrics.json: {run_dir}/metrics.json {cfg} $(STAGE_PROGRAM_cg)\n"
                     f"\t@$(call timed,$(STAGE_PROGRAM_cg) {run_dir}/{cg.run}/run.h5 --config {cfg} --out $(@D)"
                     f"{inputs}{f' --threads {threads}' if cg.threads else ''})\n")
        targets.append(f"{d}/metrics.json")

    text = ("# Written by pipeline/accuracy/plan.py from data/accuracy.toml: the accuracy sweep's rules.\n"
            f"ACCURACY_TARGETS := {' '.join(targets)}\n"
            f"# the whole-run reference and its replicas\n"
            f"ACCURACY_REFERENCE_TARGETS := {' '.join(reference_targets)}\n\n" + "\n".join(rules))
    write_if_changed(out / "plan.mk", text)


if __name__ == "__main__":
    main()
