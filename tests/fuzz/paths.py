"""make fuzz's class `paths` (tests/fuzz/fuzz.py): every path a user gives a
program replaced by what is not a regular file: a pipe nobody writes to, a
link to /dev/zero or /dev/null, a folder. The paths: dem2d's scene, overlay
and initial run, the run file of `inspect`, of the Python reader and of
every stage of the registry, each stage's settings, study constants and
inputs (the bed, the spectrum's files), and the files `dem2d run` writes in
--out (run.log, run.h5, run.xdmf).

An input must be refused: exit 2 naming the path (a pipe after at most the
10 s the programs wait for a writer), never read for ever (`hang`), never
taken as empty (`silent`); /dev/null may also be read as the empty file it
is, as long as the program then refuses what is missing or says nothing
wrong (exit 0 or 2). A special file where dem2d run writes must be refused
before the run starts, and left as it was (`destroyed` otherwise)."""
import os
import sys
from pathlib import Path

from outcomes import classify, execute

ROOT = Path(__file__).resolve().parent.parent.parent
SPECIALS = ("fifo", "dev_zero", "dev_null", "folder")
OUTPUTS = ("run.log", "run.h5", "run.xdmf")


def make_special(path: Path, special: str):
    path.parent.mkdir(parents=True, exist_ok=True)
    if special == "fifo":
        os.mkfifo(path)
    elif special == "folder":
        path.mkdir()
    else:
        path.symlink_to("/dev/zero" if special == "dev_zero" else "/dev/null")


def what_it_is(path: Path):
    """A special file's identity, to tell whether a program replaced it."""
    return (path.is_symlink() and os.readlink(path), path.is_fifo(), path.is_dir()) if os.path.lexists(path) else None


class Paths:
    def __init__(self, suite):
        self.s = suite
        self.rng = suite.rng

    def slots(self):
        """(name, program, command(path, out)): every path a user gives, as a function of what stands there."""
        s = self.s
        fill, pull = ROOT / "tests/fuzz/tiny_fill.toml", ROOT / "tests/fuzz/tiny_pulloff.toml"
        overlay = ROOT / "tests/fuzz/accept_overlap.toml"
        run = [s.dem2d, "run", "--threads", "1"]
        slots = [
            ("dem2d check:scene", "dem2d", lambda p, out: [s.dem2d, "check", p]),
            ("dem2d run:scene", "dem2d", lambda p, out: [*run, p, "--out", out, "--interrupt-at-step", "50"]),
            ("dem2d check:initial", "dem2d", lambda p, out: [s.dem2d, "check", pull, "--initial", p,
                                                             "--overlay", overlay]),
            ("dem2d check:overlay", "dem2d", lambda p, out: [s.dem2d, "check", pull, "--initial", s.fill,
                                                             "--overlay", p]),
            ("dem2d inspect:run", "dem2d", lambda p, out: [s.dem2d, "inspect", p]),
            ("python reader:run", "dem2d-python",
             lambda p, out: [sys.executable, Path(__file__).parent / "py_reader.py", p]),  # (as the reader class)
        ]
        for name in OUTPUTS:
            slots.append((f"dem2d run:out/{name}", "dem2d",
                          lambda p, out: [*run, fill, "--out", p.parent, "--interrupt-at-step", "50"]))
        for stage, reg in sorted(s.registered.items()):
            slots.append((f"{stage}:run", stage, lambda p, out, st=stage: s.stage_command(st, p, out)))
            if reg.config:
                slots.append((f"{stage}:config", stage,
                              lambda p, out, st=stage: s.stage_command(st, s.pull, out, config=p)))
            if stage != "bed_metrics":  # (the one stage without study constants)
                slots.append((f"{stage}:study", stage,
                              lambda p, out, st=stage: s.stage_command(st, s.pull, out, study=p)))
            for flag in reg.inputs:  # (the optional ones the suite does not make given here)
                def swapped(p, out, st=stage, flag=flag):
                    cmd = s.stage_command(st, s.pull, out)
                    return cmd[:cmd.index(flag) + 1] + [p] + cmd[cmd.index(flag) + 2:] if flag in cmd else cmd + [flag, p]
                slots.append((f"{stage}:{flag}", stage, swapped))
        return slots

    def run(self):
        d = self.s.fresh("paths")
        slots = self.slots()
        cases = []
        n = self.s.counts["paths"]
        # every slot once before any twice (a sample of them in a shorter run); the special drawn
        chosen = slots * (n // len(slots)) + self.rng.sample(slots, n % len(slots))
        for k, (name, program, command) in enumerate(chosen):
            cases.append((d / f"{k:04d}", name, program, command, self.rng.choice(SPECIALS)))
        for kind, outcome, what in self.s.parallel(cases, self.trial):
            self.s.record("paths", kind, outcome, what)

    def trial(self, case):
        folder, name, program, command, special = case
        out = folder / "out"
        output = ":out/" in name
        path = out / name.split("/")[-1] if output else folder / f"special_{special}"
        make_special(path, special)
        cmd = command(path, out)
        kind = f"{name}:{special}"
        before = what_it_is(path)
        r = execute(cmd, self.s.timeout)
        what = f"{path} ({name}, {special}): exit {r.rc}: {r.err.strip()[:300]}"
        if output and what_it_is(path) != before:
            return kind, "destroyed", what + ": the special file was replaced"
        if r.rc == 1 and "Traceback" in r.err:
            return kind, "traceback", what
        may_read_empty = special == "dev_null" and not output
        outcome = classify(r, program, [path], must_fail=not may_read_empty)
        if output and r.rc == 3:  # (stopped at the step asked: the run went on)
            outcome = "silent"
        return kind, outcome, what
