"""The Slurm time limit (minutes) of one ensemble member, from the parametric
study's cost model (pipeline/params/plan.py: its bed from the hopper, the
pull-off, the analyses; TIME_LIMIT_FACTOR times the estimate).

  python3 -m pipeline.slurm.member_minutes FILL_SCENE PULLOFF_SCENE [PRESET_FILE]   prints the minutes"""
import sys
from pathlib import Path

from pipeline.files import fail, read_toml
from pipeline.params import plan


def main(argv: list) -> None:
    if len(argv) not in (3, 4):
        fail("usage: python3 -m pipeline.slurm.member_minutes FILL_SCENE PULLOFF_SCENE [PRESET_FILE]")
    fill, pull = read_toml(Path(argv[1])), read_toml(Path(argv[2]))
    preset = read_toml(Path(argv[3])) if len(argv) == 4 and argv[3] else {}
    for table in ("time", "contact"):  # the preset's values over the scene's, as the overlay does
        fill[table] = {**fill.get(table, {}), **preset.get(table, {})}
    intruder = next(b for b in pull["body"] if b.get("role") == "intruder")
    speed_mm_s = 1e3 * abs(intruder["velocity"][1])
    seconds = plan.run_cost(fill, pull, None, {"pull_speed_mm_s": speed_mm_s}, {"fill": "hopper"}, fill, True)
    print(plan.task_minutes(seconds))


if __name__ == "__main__":
    main(sys.argv)
