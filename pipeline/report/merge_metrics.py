"""Merges the stages' metrics into one file, with the run's cost.

    /usr/bin/python3 -m pipeline.report.merge_metrics RESULTS_DIR PRESET [FILL_RUN]

FILL_RUN: the bed's run file when it is not RESULTS_DIR/fill/run.h5 (make
accuracy starts its sweep points from beds made elsewhere).

Reads RESULTS_DIR/<stage>/metrics.json (each {"<stage>": {...}}) for every
stage of the registry (pipeline/stages.toml), the engine's own timing of
the two simulations (run.h5 attributes: wall time, steps, threads) for the
stages named like them, and the Makefile's timing of the other stages
(RESULTS_DIR/<stage>/timing.json), and writes RESULTS_DIR/metrics.json:

    {"preset": ..., "fill": {...}, "pulloff": {...}, "spectrum": {...}, "cg": {...},
     "network": {...}, "friction": {...},
     "cost": {"<stage>": {"wall_seconds": ..., ...}, "total_wall_seconds": ...}}

A missing or unreadable input stops with a message naming the file and the
make target that writes it (exit code 2).
"""
import json
import sys
from pathlib import Path

from pipeline.files import fail, read_json, stages, write_atomic

SIMULATIONS = ["fill", "pulloff"]


def simulation_cost(run_file: Path, preset: str, stage: str) -> tuple[dict, str]:
    """The run's cost (engine wall time, steps, ...) and the code version that ran it."""
    import dem2d  # the run-file reader (python/dem2d; the pipeline package puts it on the path)

    try:
        with dem2d.open_run(run_file) as r:
            a = r.attrs
            steps, n, wall = int(a["steps"]), int(a["n_particles"]), float(a["wall_seconds"])
            cost = {"wall_seconds": wall, "steps": steps, "particles": n, "threads": int(a["threads"]),
                    "simulated_seconds": float(a["end_time"]), "time_step_s": float(a["dt"])}
            version = a["code_version"]
    except (OSError, KeyError, ValueError) as e:
        fail(f"{run_file}: cannot read the run's cost ({e}): run `make {stage} PRESET={preset}`")
    if steps > 0 and wall > 0:
        cost["ns_per_particle_step"] = wall * 1e9 / (steps * n)
        cost["particle_steps_per_second"] = steps * n / wall
    return cost, str(version)


def main() -> None:
    if len(sys.argv) not in (3, 4):
        fail("usage: python3 -m pipeline.report.merge_metrics RESULTS_DIR PRESET [FILL_RUN]")
    results, preset = Path(sys.argv[1]), sys.argv[2]
    runs = {stage: results / stage / "run.h5" for stage in SIMULATIONS}
    if len(sys.argv) == 4:
        runs["fill"] = Path(sys.argv[3])
    merged = {"preset": preset, "code_version": ""}  # the pull-off's, filled in below
    cost = {}
    registry = stages()
    for s in registry:
        stage = s.name
        metrics = read_json(results / stage / "metrics.json", f"make {stage} PRESET={preset}")
        if stage not in metrics:
            fail(f"{results / stage / 'metrics.json'}: no \"{stage}\" object: rerun `make {stage} PRESET={preset}`")
        merged[stage] = metrics[stage]
        if s.is_simulation_report:
            cost[stage], merged["code_version"] = simulation_cost(runs[stage], preset, stage)
        else:
            cost[stage] = read_json(results / stage / "timing.json", f"make {stage} PRESET={preset}")
    cost["total_wall_seconds"] = sum(c["wall_seconds"] for c in cost.values())
    merged["cost"] = cost
    write_atomic(results / "metrics.json", json.dumps(merged, indent=2) + "\n")
    print(f"merge_metrics: {len(registry)} stages -> {results / 'metrics.json'}", file=sys.stderr)


if __name__ == "__main__":
    main()
