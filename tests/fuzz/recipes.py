"""make fuzz's `pipeline` kind `recipe` (tests/fuzz/layers.py): a recipe of
`make reproduce` (a simulation or a stage) that writes its outputs and then
fails (exit 1 or 2, or killed). The programs are stand-ins (a build folder of one script under
every program's name): each writes what its program writes in --out (the
registry's outputs, a run's files) and succeeds, except the victim, which
writes them and then fails. The oracle: make ends non-zero, and the next
`make -n` plans the victim's command again: a failed recipe never leaves a
target that make later takes as done (`fault`), whatever it wrote.
"""
import os
import shutil
import stat
from pathlib import Path

from outcomes import execute

FAKE = r"""#!/usr/bin/env bash
# a stand-in for one of the pipeline's programs (tests/fuzz/recipes.py)
name=$(basename "$0")
out="" prev=""
for a in "$@"; do
  [ "$prev" = --out ] && out=$a
  case $a in --gtest_output=json:*) echo '{}' >"${a#--gtest_output=json:}" ;; esac
  prev=$a
done
if [ -n "$out" ]; then
  mkdir -p "$out"
  var="OUTPUTS_$name"
  for f in ${!var}; do mkdir -p "$(dirname "$out/$f")"; echo "written by a stand-in" >"$out/$f"; done
fi
if [ "$name" = "$FAKE_VICTIM" ]; then
  case $FAKE_HOW in
    exit1) exit 1 ;;
    exit2) exit 2 ;;
    killed) kill -9 $$ ;;
  esac
fi
exit 0
"""
HOWS = ("exit1", "exit2", "killed")


def stand_ins(build: Path, registered: dict):
    """A build folder whose programs are the stand-in: sim/dem2d, analysis/<stage>, the targets' check."""
    programs = [build / "sim/dem2d", build / "tests/paper_targets/check_paper_targets",
                *[build / "analysis" / p for p in registered]]
    for p in programs:
        p.parent.mkdir(parents=True, exist_ok=True)
        p.write_text(FAKE)
        p.chmod(p.stat().st_mode | stat.S_IXUSR | stat.S_IXGRP | stat.S_IXOTH)
    env = {f"OUTPUTS_{p}": " ".join(["metrics.json", *s.outputs]) for p, s in registered.items()}
    env["OUTPUTS_dem2d"] = "run.h5 run.xdmf run.log"
    return env


def recipe(pipeline, case):
    """One trial: (outcome, kind, what)."""
    rng, registered = pipeline.rng, pipeline.s.registered
    build, results = case / "build", case / "results"
    env = dict(os.environ, **stand_ins(build, registered))
    victim = rng.choice(["dem2d", *registered])
    how = rng.choice(HOWS)
    env.update(FAKE_VICTIM=victim, FAKE_HOW=how)
    # (the victim is a simulation or a stage: the report's steps after them would read the stand-ins' files)
    args = ["reproduce", "PRESET=quick", f"RESULTS={results}", f"BUILD={build}", "PROGRAMS_BUILT=1"]
    kind = f"{victim}:{how}"
    r = execute(["make", "--no-print-directory", "-C", pipeline.repo, *args], pipeline.s.timeout, env=env)
    what = f"make reproduce, {victim} writes its outputs and then {how}: exit {r.rc}: {r.err.strip()[-300:]}"
    if r.rc is None:
        return "hang", kind, what
    if r.rc == 0:
        return "silent", kind, what
    again = execute(["make", "--no-print-directory", "-n", "-C", pipeline.repo, *args], pipeline.s.timeout, env=env)
    plan = again.out + again.err
    program = str(build / ("sim" if victim == "dem2d" else "analysis") / victim)
    shutil.rmtree(case, ignore_errors=True)
    if program not in plan:
        return "fault", kind, what + f"; the next make -n does not rerun it: {plan.strip()[-300:]}"
    return "error", kind, what  # (make refused to go on, and will make it again)
