"""make fuzz's class `pipeline` (tests/fuzz/fuzz.py): the layers above the
engine fed what a careless or hostile user gives them. Kinds:

  registry  a mutated or hostile stage registry: pipeline/stages.py refuses it
            (exit 2 naming it), or make -n reproduce runs with it, and
            nothing from it runs, overrides a Makefile variable or recipe, or
            changes what make does with the project's own registry
  make      a user variable (MEMBERS, JOBS, THREADS, PROGRESS, PRESET,
            INTRUDER) with a random value: make -n accepts exactly the values
            the rule allows, refuses the rest naming the variable
  aggregate an ensemble of three members, one damaged (a metric, its
            document, its drag profile): the aggregate refuses exactly the
            damage, naming the member, and writes nothing then
  outdir    dem2d run into a folder holding what a user left there (their
            run.h5 or run.xdmf, links out of it, files in .run.work, a lock
            held, the run's own --initial): a user's file is never replaced
            or deleted unless --overwrite names it, nothing is written
            through a link, and the run refuses exactly what it must
  recipe    a recipe of make reproduce writes its outputs and then fails or is
            killed (tests/fuzz/recipes.py): make ends non-zero and plans it
            again; nothing it wrote is taken as done

Everything runs in a copy of the repository's files (make's outputs and the
generated rules stay there)."""
import fcntl
import hashlib
import json
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import mutate
from outcomes import classify, execute
from pipeline import stages as stage_registry
from recipes import recipe

ROOT = Path(__file__).resolve().parent.parent.parent
COUNT_VARS = {"MEMBERS": (1, 1000), "JOBS": (1, 1024), "THREADS": (1, 1024), "PROGRESS": (1, 86400)}
# the Makefile's own variables, which a registry must leave alone
OWN_VARS = ("SHELL", "PYTHON", "PATH", "BUILD", "RESULTS", "PRESET", "MEMBERS", "THREADS", "JOBS", "DEM2D",
            "STAGE_BIN", "EXECUTOR", "INSTALLED", "PREFIX")


def named_error(r, names):
    """classify() for tools whose message need not start with their name (make, Python scripts)."""
    if r.rc is None:
        return "hang"
    if "Traceback (most recent call last)" in r.err:
        return "traceback"
    if r.rc != 2:
        return "ok" if r.rc == 0 else "message"
    named = any(str(n) in r.err for n in names)
    return "error" if named and len(r.err) <= 4000 else "message"


def digest(path: Path):
    """What a file or link is, to tell whether it changed (None: absent)."""
    if path.is_symlink():
        return "link:" + os.readlink(path)
    if path.is_file():
        return hashlib.sha256(path.read_bytes()).hexdigest()
    return "dir" if path.is_dir() else None


class Pipeline:
    def __init__(self, suite):
        self.s = suite
        self.rng = suite.rng

    def run(self):
        d = self.s.fresh("pipeline")
        self.repo = d / "repo"
        files = subprocess.run(["git", "-C", str(ROOT), "ls-files", "-z"], capture_output=True, check=True).stdout
        for rel in filter(None, files.decode().split("\0")):
            if (ROOT / rel).is_file():
                (self.repo / rel).parent.mkdir(parents=True, exist_ok=True)
                shutil.copy2(ROOT / rel, self.repo / rel)
        self.canary = d / "CANARY"
        self.base_vars = self.make_vars(self.repo / "pipeline/stages.toml")
        self.base_plan = self.make(["-n", "reproduce", "PRESET=quick"])
        if self.base_plan.rc != 0 or self.base_vars is None:
            sys.exit(f"fuzz: make -n reproduce fails in the copy of the repository:\n{self.base_plan.err[-2000:]}")
        kinds = {"registry": self.registry, "make": self.make_kind, "aggregate": self.aggregate,
                 "outdir": self.outdir, "recipe": lambda case: recipe(self, case)}
        for k in range(self.s.counts["pipeline"]):  # one at a time: the canary and make's rules are shared
            name = list(kinds)[k % len(kinds)]
            outcome, kind, what = kinds[name](d / f"{k:04d}")
            self.s.record("pipeline", f"{name}:{kind}", outcome, what)
        again = self.make(["-n", "reproduce", "PRESET=quick"])
        if again.rc != 0 or again.err != self.base_plan.err:
            self.s.record("pipeline", "registry", "fault", "make -n reproduce with the project's registry changed "
                          f"after the trials: {again.err[-300:]}")

    def make(self, args, timeout=None):
        return execute(["make", "--no-print-directory", "-C", self.repo, *args], timeout or self.s.timeout)

    def make_vars(self, registry):
        probe = "fuzzvars: ; @printf '%s\\n' " + " ".join(f"'$({v})'" for v in OWN_VARS)
        p = subprocess.run(["make", "-s", "--no-print-directory", "-C", str(self.repo), f"--eval={probe}", "fuzzvars",
                            f"STAGE_REGISTRY={registry}"], capture_output=True, text=True, timeout=self.s.timeout)
        return p.stdout if p.returncode == 0 else None

    def ran(self):
        if self.canary.exists():
            self.canary.unlink()
            return True
        return False

    def pipeline_module(self, module, *args):
        """A program of the repository's pipeline package (python3 -m module args...)."""
        return execute([sys.executable, "-m", module, *args], self.s.timeout,
                       env={**os.environ, "PYTHONPATH": str(self.repo)})

    # ---- the stage registry ----
    def hostile_stage(self):
        """A stage valid but for one field (so that what that field does reaches make when it is taken)."""
        canary = str(self.canary)
        options = {  # the first of each is valid
            "name": ['"extra"', *(f'"{n}"' for n in ("build", "install", "test", "check", "ensemble", "cyclic", "needs",
                                                      "clean", "reproduce", "figures", "metrics", "params", "fill",
                                                      "pulloff", "Extra", "a" * 70, "x-y", "python", "shell"))],
            "program": ['"friction"', *(f'"{p}"' for p in ("python", "path", "shell", "check", "threads", "members",
                                                            "results", "p" * 70, "a b", "../x"))],
            "args": ["[]", *("[" + ", ".join(json.dumps(a) for a in args) + "]" for args in (
                ["a b"], [f"; touch {canary}"], [f"$(shell touch {canary})"], ["# x"], [f"`touch {canary}`"],
                [f"$$(touch {canary})"], ["it's"], ["--out={dir}/x"], ["\\"], ["%", "a,b", "(x)"],
                [f"\" ; touch {canary} ; \""], ["a\nb"]))],
            "config": ['"data/friction.toml"', '"/etc/hostname"', '"../x.toml"', '"data/../../x.toml"', "3", '""',
                       '"data/no_such.toml"', '"data/friction.toml; x"'],
            "inputs": ["{}", '{ "--x; y" = "fill/run.h5" }', '{ "--events" = "spectrum/spectrum.h5" }',
                       '{ "--a" = "nope/x" }', '"x"'],
            "outputs": ['["friction.h5", "metrics.json"]', '["../a", "metrics.json"]', '["x y", "metrics.json"]',
                        "[]", '["a.h5"]', '"metrics.json"'],
        }
        field = self.rng.choice(list(options))
        value = {k: (self.rng.choice(v[1:]) if k == field else v[0]) for k, v in options.items()}
        return (f"hostile_{field}", f'\n[[stage]]\nname = {value["name"]}\nprogram = {value["program"]}\n'
                f'run = "pulloff"\nconfig = {value["config"]}\ninputs = {value["inputs"]}\nargs = {value["args"]}\n'
                f'outputs = {value["outputs"]}\n')

    def registry(self, case):
        base = (self.repo / "pipeline/stages.toml").read_text()
        if self.rng.random() < 0.5:
            kind, extra = self.hostile_stage()
            text = base + extra
        else:
            kind, text = mutate.mutate_toml(self.rng, base)
        path = case.with_suffix(".stages.toml")
        path.write_text(text, errors="surrogateescape")
        r = self.pipeline_module("pipeline.stages", "make", path)
        verdict = named_error(r, [path])
        plan = self.make(["-n", "reproduce", "PRESET=quick", f"STAGE_REGISTRY={path}"])
        what = f"{path} ({kind}): stages.py exit {r.rc}: {r.err.strip()[:300]}"
        if self.ran():
            return "ran", kind, what + " (a command from the registry ran)"
        if verdict != "ok":
            if verdict == "error" and plan.rc == 0:
                return "disagree", kind, what + ": make -n reproduce accepted it"
            return verdict, kind, what
        if plan.rc != 0:
            return "disagree", kind, what + f"; make -n reproduce: {plan.err.strip()[-300:]}"
        if "overriding recipe" in plan.err or "ignoring old recipe" in plan.err:
            return "ran", kind, what + f": a Makefile recipe overridden: {plan.err.strip()[:300]}"
        if self.make_vars(path) != self.base_vars:
            return "ran", kind, what + ": the Makefile's own variables changed"
        return "ok", kind, what

    # ---- make's user variables ----
    def make_case(self):
        r = self.rng
        var = r.choice([*COUNT_VARS, "PRESET", "INTRUDER"])
        canary = str(self.canary)
        value = r.choice(["1", "2", "4", "010", "08", "0", "-1", "+3", "1000", "1001", "86400", "86401", "1000000",
                          "99999999999", "1e3", "0x10", "4.0", " 4", "4 ", "", "a b", "fast", "quick", "default",
                          "paper", "../../pipeline/presets/fast", "pipeline/presets/fast", "fast.toml", "square",
                          "round", f"; touch {canary}", f"`touch {canary}`", f"'; touch {canary}; '", "\u0663",
                          "\uff14", "fast default", "%", "*", "quick\\", "#"])
        return var, value

    @staticmethod
    def allowed(var, value):
        value = value.lstrip(" ")  # (make drops the blanks that open a command line's value)
        if var == "THREADS" and value == "":
            return True  # unset: each simulation chooses
        if var in COUNT_VARS:
            lo, hi = COUNT_VARS[var]
            return bool(re.fullmatch(r"[1-9][0-9]{0,8}", value)) and lo <= int(value) <= hi
        if var == "PRESET":
            return value in ("quick", "default", "fast", "paper")
        return value in ("", "square")  # INTRUDER: unset, or a file of pipeline/intruders

    def make_kind(self, case):
        var, value = self.make_case()
        target = "ensemble" if var == "MEMBERS" else "reproduce"
        preset = [] if var == "PRESET" else ["PRESET=quick"]
        r = self.make(["-n", target, *preset, f"{var}={value}"])
        what = f"make -n {target} {var}={value!r}: exit {r.rc}: {r.err.strip()[-300:]}"
        if self.ran():
            return "ran", var, what
        if r.rc is None:
            return "hang", var, what
        if self.allowed(var, value):
            return ("ok" if r.rc == 0 else "fault"), var, what
        if r.rc == 0:
            return "silent", var, what
        return ("error" if r.rc == 2 and f"{var}=" in r.err and len(r.err) <= 4000 else "message"), var, what

    # ---- the ensemble aggregate ----
    def aggregate(self, case):
        stages = [s.name for s in stage_registry.load(self.repo / "pipeline/stages.toml")]
        dirs = []
        for k in range(3):
            m = case / f"member_{k:03d}"
            (m / "pulloff").mkdir(parents=True)
            doc = {"preset": "quick", "code_version": "x"}
            for j, s in enumerate(stages):
                doc[s] = {"a": 0.5 + 0.01 * k + j, "none": None, "note": "text", "sub": {"b": -2.0 + k},
                          "cost": {"wall_seconds": 3.0 + k}}
            (m / "metrics.json").write_text(json.dumps(doc))
            (m / "pulloff/drag.csv").write_text("height_mm,drag_N_per_m\n0.5,10\n1.5,12\n2.5,9\n")
            dirs.append(m)
        victim = dirs[1]
        kind, must_fail = self.damage_member(victim, stages)
        out = case / "ensemble"
        r = self.pipeline_module("pipeline.ensemble.aggregate", "--registry", self.repo / "pipeline/stages.toml", out,
                                 "quick", *dirs)
        what = f"{victim} ({kind}): exit {r.rc}: {r.err.strip()[:300]}"
        verdict, kind = named_error(r, [victim]), kind.split(" ")[0]
        if verdict == "ok":
            return ("silent" if must_fail else "ok"), kind, what
        if verdict == "error" and (not must_fail or out.exists() and any(out.iterdir())):
            return "fault", kind, what + " (valid members refused, or files written)"
        return verdict, kind, what

    def damage_member(self, m, stages):
        """One damage to member m: (what, whether the aggregate must refuse it)."""
        r = self.rng
        path, drag = m / "metrics.json", m / "pulloff/drag.csv"
        doc = json.loads(path.read_text())
        stage = r.choice(stages)
        choice = r.randrange(3)
        if choice == 0:  # one metric's value
            value, bad = r.choice([("NaN", True), ("Infinity", True), ("-Infinity", True), ('"0.2"', True),
                                   ("true", True), ("[0.2]", True), ('{"x": 1}', True), ("1" + "0" * 400, True),
                                   ("1e308", False), ("null", False), ("-0.0", False), ("1e-320", False)])
            key = r.choice(["a", "sub.b"])
            (doc[stage] if key == "a" else doc[stage]["sub"])[key[-1]] = "@VALUE@"
            path.write_text(json.dumps(doc).replace('"@VALUE@"', value))
            return f"value {stage}.{key}={value[:12]}", bad
        if choice == 1:  # the document
            kind = r.choice(["delete_metric", "delete_stage", "preset", "list", "number", "null", "empty_object",
                             "empty_file", "cut", "junk", "deleted", "extra_key"])
            text = json.dumps(doc)
            if kind == "delete_metric":
                del doc[stage]["a"]
            elif kind == "delete_stage":
                del doc[stage]
            elif kind == "preset":
                doc["preset"] = "default"
            elif kind == "extra_key":
                doc[stage]["extra"] = "words"
            new = {"list": "[]", "number": "3", "null": "null", "empty_object": "{}", "empty_file": "",
                   "cut": text[:r.randrange(1, len(text))], "junk": "\x00\xff{]"}.get(kind, json.dumps(doc))
            if kind == "deleted":
                path.unlink()
            else:
                path.write_text(new, errors="surrogateescape")
            return f"document {kind}", kind != "extra_key"
        kind, text, bad = r.choice([
            ("cut", "height_mm,drag_N_per_m\n0.5,10\n1.5", True), ("header_only", "height_mm,drag_N_per_m\n", True),
            ("nan", "height_mm,drag_N_per_m\n0.5,nan\n", True), ("huge_height", "height_mm,drag_N_per_m\n1e12,3\n", True),
            ("negative_height", "height_mm,drag_N_per_m\n-2.5,7\n0.5,10\n", False), ("junk", "\x00\xff,,\n", True),
            ("deleted", None, True), ("no_column", "height_mm\n0.5\n", True),
            ("extra_column", "height_mm,drag_N_per_m,x\n0.5,10,1\n", False)])
        if text is None:
            drag.unlink()
        else:
            drag.write_text(text, errors="surrogateescape")
        return f"drag {kind}", bad

    # ---- dem2d run's output folder ----
    SETUPS = ("user_run_h5", "user_xdmf", "log_link", "h5_link", "work_link", "foreign_in_work", "user_tmp",
              "user_other", "out_is_file", "initial_run_h5", "initial_below", "locked", "user_log", "earlier_run")

    def outdir(self, case):
        setup = self.rng.choice(self.SETUPS)
        overwrite = self.rng.random() < 0.3
        out, outside = case / "out", case / "outside"
        outside.mkdir(parents=True)
        (outside / "theirs.txt").write_text("a user's file elsewhere\n")
        scene, initial = ROOT / "tests/fuzz/tiny_fill.toml", None
        lock = None
        if setup != "out_is_file":
            out.mkdir()
        if setup == "user_run_h5":
            (out / "run.h5").write_bytes(os.urandom(4096))
        elif setup == "user_xdmf":
            (out / "run.xdmf").write_text("<xml>a user's</xml>\n")
        elif setup in ("log_link", "h5_link"):
            (out / ("run.log" if setup == "log_link" else "run.h5")).symlink_to(outside / "theirs.txt")
        elif setup == "work_link":
            (out / ".run.work").symlink_to(outside)
        elif setup == "foreign_in_work":
            (out / ".run.work").mkdir()
            (out / ".run.work/mine.txt").write_text("mine\n")
        elif setup == "user_tmp":
            (out / "run.h5.tmp").write_text("a user's\n")
            (out / "run.xdmf.tmp").write_text("a user's\n")
        elif setup == "user_other":
            (out / "notes.txt").write_text("a user's\n")
        elif setup == "user_log":
            (out / "run.log").write_text("a user's log\n")
        elif setup == "out_is_file":
            out.write_text("a user's file\n")
        elif setup in ("initial_run_h5", "initial_below"):
            scene = ROOT / "tests/fuzz/tiny_pulloff.toml"
            initial = out / ("run.h5" if setup == "initial_run_h5" else "beds/bed.h5")
            initial.parent.mkdir(exist_ok=True)
            shutil.copy(self.s.fill, initial)
        elif setup == "locked":
            lock = open(out / ".run.lock", "w")
            lock.write("12345")
            lock.flush()
            fcntl.flock(lock, fcntl.LOCK_EX)
        elif setup == "earlier_run":
            shutil.copy(self.s.pull, out / "run.h5")  # a dem2d run file: dem2d's own, replaced by a new run
        before = {p: digest(p) for p in [*self.tree(case)]}
        cmd = [self.s.dem2d, "run", scene, "--out", out, "--threads", "1"]
        cmd += ["--initial", initial] if initial else ["--interrupt-at-step", "2000"]
        cmd += ["--overwrite"] if overwrite else []
        r = execute(cmd, self.s.timeout)
        if lock:
            lock.close()
        kind = f"{setup}{'+overwrite' if overwrite else ''}"
        what = f"{out} ({setup}{', --overwrite' if overwrite else ''}): exit {r.rc}: {r.err.strip()[:300]}"
        must_fail = setup in ("log_link", "h5_link", "work_link", "foreign_in_work", "out_is_file", "initial_run_h5",
                              "initial_below", "locked") or setup in ("user_run_h5", "user_xdmf") and not overwrite
        may_change = {out / "run.h5", out / "run.xdmf"} if overwrite or setup == "earlier_run" else set()
        for p, was in before.items():
            now = digest(p)
            if p == out / "run.log" and setup == "user_log" and now and p.read_text().startswith("a user's log\n"):
                continue  # (a log is appended to)
            if was not in (None, "dir") and now != was and p not in may_change and p.parent != out / ".run.work":
                return ("foreign" if outside in p.parents else "destroyed"), kind, what + f": {p} changed"
        outcome = "ok" if r.rc == 3 else classify(r, "dem2d", [out])  # 3: stopped at the step asked
        if outcome == "ok":
            return ("silent" if must_fail else "ok"), kind, what
        if outcome == "error" and not must_fail:
            return "fault", kind, what + " (refused a folder it may use)"
        return outcome, kind, what

    @staticmethod
    def tree(case):
        for dirpath, dirnames, filenames in os.walk(case):
            for n in dirnames + filenames:
                yield Path(dirpath) / n
