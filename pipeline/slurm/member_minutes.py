#!/usr/bin/python3
"""The Slurm time limit (minutes) of one ensemble member, from the parametric
study's cost model (pipeline/params/plan.py: its bed from the hopper, the
pull-off, the analyses; TIME_LIMIT_FACTOR times the estimate).

  member_minutes.py FILL_SCENE PULLOFF_SCENE [PRESET_FILE]   prints the minutes"""
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))
sys.path.insert(0, str(HERE.parent / "report"))
sys.path.insert(0, str(HERE.parent / "params"))
from files import fail, read_toml  # noqa: E402
import plan  # noqa: E402

if len(sys.argv) not in (3, 4):
    fail("usage: member_minutes.py FILL_SCENE PULLOFF_SCENE [PRESET_FILE]")
fill, pull = read_toml(Path(sys.argv[1])), read_toml(Path(sys.argv[2]))
preset = read_toml(Path(sys.argv[3])) if len(sys.argv) == 4 and sys.argv[3] else {}
for table in ("time", "contact"):  # the preset's values over the scene's, as the overlay does
    fill[table] = {**fill.get(table, {}), **preset.get(table, {})}
intruder = next(b for b in pull["body"] if b.get("role") == "intruder")
speed_mm_s = 1e3 * abs(intruder["velocity"][1])
seconds = plan.run_cost(fill, pull, None, {"pull_speed_mm_s": speed_mm_s}, {"fill": "hopper"}, fill, True)
print(plan.task_minutes(seconds))
