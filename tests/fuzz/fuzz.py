#!/usr/bin/python3
"""The input-and-fault suite (make fuzz; a short version in make test).

  fuzz.py --bin DIR [--quick] [--seed N] [--counts CLASS=N,...] [--work DIR] [--only CLASS,...] [--setup-only | --base DIR]

DIR holds sim/dem2d and analysis/<stage> (a build tree: build/release or
build/sanitize). Deterministic for a seed. Classes:
  scene    mutated scenes (from tests/scenes, examples/, tests/fuzz): dem2d
           check, then dem2d run of what check accepts (a few hundred steps)
  config   mutated stage settings (data/<stage>.toml) and study constants
           (data/study.toml), each stage on the suite's pull-off run
  runfile  corrupted copies of that run file, read by every stage and by
           dem2d check --initial
  reader   corrupted copies of the run file read whole by both readers, the
           C++ one (dem2d inspect) and the Python one (python/dem2d,
           check_run): their verdicts must agree, and both refuse damage
  fault    SIGKILL, SIGTERM, SIGINT at random moments, a full disk (a file
           size limit), a damaged work directory: the rerun must resume to a
           run file bitwise identical to the uninterrupted one, or refuse and
           say --fresh; a run file that exists is never wrong
  pipeline the layers above the engine (tests/fuzz/layers.py): mutated and
           hostile stage registries, make's user variables, damaged ensemble
           members, dem2d run into folders holding a user's files
  install  the installed programs with their share/ moved or missing, another
           installation's beside them, DEM2D_SHARE good or bad
           (tests/fuzz/install.py)
  paths    a pipe nobody writes to, a link to /dev/zero or /dev/null, or a
           folder at every path a user gives a program (tests/fuzz/paths.py)
  slurm    quick ensembles through a real one-node Slurm with a failing
           member, a lost node, a cancelled job, a resubmission or a killed
           controller
           (tests/fuzz/cluster.py; root; none in --quick)
Outcomes per input: ok (accepted), error (exit 2, bad input, the message
names the file), failed (exit 1 with a message: out of memory, a run that
diverges, a damaged work directory), and the defects: crash (a signal or
another exit code), sanitizer (an ASan/UBSan report), hang (no exit within
the time limit), message (exit 2 whose message does not name the file, or is
too long), disagree (check accepts what run refuses; the two readers differ),
traceback (a Python tool fails with its own exception), silent (exit 0 on an
input the program must refuse), fault (a resume that differs or a wrong
file), ran (text of an input ran as a command or changed the Makefile), destroyed
(a user's file replaced or deleted), foreign (another installation's data used,
a file outside the output folder written). Prints counts per class and
outcome; exit 1 if any defect."""
import argparse
import collections
import os
import random
import resource
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import h5py

ROOT = Path(__file__).resolve().parent.parent.parent
sys.path.insert(0, str(ROOT))  # the repository under test: its pipeline package
import mutate  # noqa: E402  (this folder's modules: a script's folder is on the path)
from cluster import Cluster  # noqa: E402
from install import Install  # noqa: E402
from layers import Pipeline  # noqa: E402
from paths import Paths  # noqa: E402

import pipeline  # noqa: E402,F401  (puts the tree's run-file reader, python/dem2d, first on the path)
from dem2d import schema  # noqa: E402
from outcomes import DEFECTS, classify, execute  # noqa: E402
from pipeline import stages as registry  # noqa: E402

# every analysis program of the stage registry (pipeline/stages.toml) is a consumer of the run files
REGISTERED = {s.program: s for s in registry.load()}
STAGES = tuple(REGISTERED)
SCENES = ["tests/scenes/valid_minimal.toml", "tests/scenes/quick_fill.toml", "examples/box/scene.toml",
          "examples/silo/scene.toml", "tests/fuzz/tiny_fill.toml", "tests/fuzz/tiny_pulloff.toml"]
COUNTS = {"quick": {"scene": 40, "config": 30, "runfile": 10, "reader": 16, "fault": 6, "pipeline": 20,
                    "install": 6, "paths": 12, "slurm": 0},
          "full": {"scene": 1200, "config": 700, "runfile": 300, "reader": 400, "fault": 40, "pipeline": 400,
                   "install": 60, "paths": 200, "slurm": 6}}
CLASSES = ("scene", "config", "runfile", "reader", "fault", "pipeline", "install", "paths", "slurm")
TIMEOUT = 60.0  # s per program run (x 4 in a sanitizer build)


# A file HDF5 could not flush stays in its memory until the exit: LeakSanitizer's report of it is expected
# in the full-disk trials, and only there (lsan_full_disk.supp).
FULL_DISK_ENV = dict(os.environ, LSAN_OPTIONS=":".join(
    filter(None, [os.environ.get("LSAN_OPTIONS"), f"suppressions={Path(__file__).resolve().parent / 'lsan_full_disk.supp'}"])))


def counts_option(text):
    """--counts CLASS=N,...: the classes' case counts it sets (N a whole number >= 1)."""
    counts = {}
    for item in filter(None, text.split(",")):
        cls, _, n = item.partition("=")
        if cls not in CLASSES or not n.isdigit() or int(n) < 1:
            sys.exit(f"fuzz: --counts {text}: {item!r}: expected CLASS=N with CLASS one of {', '.join(CLASSES)} "
                     "and N a whole number >= 1")
        counts[cls] = int(n)
    return counts


class Suite:
    def __init__(self, args):
        self.bin = Path(args.bin).resolve()
        self.dem2d = self.bin / "sim" / "dem2d"
        self.analysis = self.bin / "analysis"
        self.rng = random.Random(args.seed)
        self.work = Path(args.work)
        self.timeout = TIMEOUT * (4 if "sanitize" in str(self.bin) else 1)
        self.counts = dict(COUNTS["quick" if args.quick else "full"], **counts_option(args.counts))
        self.table = collections.defaultdict(collections.Counter)  # (class, kind) -> outcome counts
        self.defects = []
        self.failures = []  # exit 1 with a message: not defects, listed for a look
        self.jobs = args.jobs
        self.registered = REGISTERED

    def fresh(self, name):
        """An empty folder for one class's inputs and outputs."""
        d = self.work / name
        shutil.rmtree(d, ignore_errors=True)
        d.mkdir(parents=True)
        return d

    def record(self, cls, kind, outcome, what):
        self.table[(cls, kind)][outcome] += 1
        if outcome in DEFECTS:
            self.defects.append(f"{cls}/{kind}: {outcome}: {what}")
        elif outcome == "failed":
            self.failures.append(f"{cls}/{kind}: {what}")

    # ---- the valid inputs everything starts from ----
    def setup(self, base=None):
        """The valid fill, pull-off and spectrum every class mutates, checked by every consumer; made
        here, or (base) taken from a folder an earlier `--setup-only` made (ctest's fixture fuzz_base)."""
        if base is not None:
            d = Path(base).resolve()
            self.fill, self.pull = d / "fill/run.h5", d / "pull/run.h5"
            self.events, self.spectrum_metrics = d / "spectrum/spectrum.h5", d / "spectrum/metrics.json"
            missing = [p for p in (self.fill, self.pull, self.events, self.spectrum_metrics) if not p.exists()]
            if missing:
                sys.exit(f"fuzz: --base {base}: {missing[0]} does not exist (made by fuzz.py --setup-only)")
            return
        d = self.fresh("base")
        fill, pull = d / "fill", d / "pull"
        for cmd in ([self.dem2d, "run", ROOT / "tests/fuzz/tiny_fill.toml", "--out", fill],
                    [self.dem2d, "run", ROOT / "tests/fuzz/tiny_pulloff.toml", "--initial", fill / "run.h5", "--out", pull],
                    [self.analysis / "spectrum", pull / "run.h5", "--out", d / "spectrum"]):
            r = execute(cmd, self.timeout * 5)
            if r.rc != 0:
                sys.exit(f"fuzz: the valid base failed: {' '.join(map(str, cmd))}:\n{r.err}")
        self.fill, self.pull = fill / "run.h5", pull / "run.h5"
        self.events, self.spectrum_metrics = d / "spectrum/spectrum.h5", d / "spectrum/metrics.json"
        # every consumer accepts the valid run file, or the oracle means nothing
        for name, cmd in self.consumers(self.pull, d / "valid").items():
            r = execute(cmd, self.timeout)
            if r.rc != 0:
                sys.exit(f"fuzz: {name} refuses the valid pull-off run:\n{r.err}")

    def stage_command(self, stage, run, out, config=None, study=None):
        """The program `stage` on `run`, with the registry's inputs the base holds (the bed, the
        spectrum's events and metrics; the others are optional: --fill-metrics, --cg-metrics)."""
        cmd = [self.analysis / stage, run, "--out", out]
        base = {registry.BED: self.fill, "spectrum/spectrum.h5": self.events,
                "spectrum/metrics.json": self.spectrum_metrics}
        for flag, source in REGISTERED[stage].inputs.items():
            if source in base:
                cmd += [flag, base[source]]
        if config:
            cmd += ["--config", config]
        if study:
            cmd += ["--study", study]
        return cmd

    def consumers(self, run, out):
        c = {s: self.stage_command(s, run, out / s) for s in STAGES}
        c["dem2d_initial"] = [self.dem2d, "check", ROOT / "tests/fuzz/tiny_pulloff.toml", "--initial", run,
                              "--overlay", ROOT / "tests/fuzz/accept_overlap.toml"]
        return c

    def parallel(self, items, fn):
        with ThreadPoolExecutor(self.jobs) as pool:
            return list(pool.map(fn, items))

    # ---- scenes ----
    def scenes(self):
        d = self.fresh("scene")
        cases = []
        for k in range(self.counts["scene"]):
            base = ROOT / self.rng.choice(SCENES)
            kind, text = mutate.mutate_toml(self.rng, base.read_text())
            path = d / f"{k:05d}_{base.stem if base.stem != 'scene' else base.parent.name}.toml"
            path.write_text(text, errors="surrogateescape")
            cases.append((kind, path, base.name == "tiny_pulloff.toml"))

        def one(case):
            kind, path, needs_bed = case
            extra = ["--initial", self.fill] if needs_bed else []
            r = execute([self.dem2d, "check", path, *extra], self.timeout)
            outcome = classify(r, "dem2d", [path])
            if outcome == "ok":
                out = path.with_suffix("")
                run = execute([self.dem2d, "run", path, *extra, "--out", out, "--threads", "1",
                               "--interrupt-at-step", "300"], self.timeout)
                outcome = "ok" if run.rc == 3 else classify(run, "dem2d", [path])  # 3: stopped at the step asked
                # a value at the edge of its type that check accepts must run: refused, out of memory or
                # diverging at once, it is one check should have refused
                if outcome == "error" or (outcome == "failed" and kind in ("int_width", "float_edge")):
                    outcome = "disagree"
                r = run
                shutil.rmtree(out, ignore_errors=True)
            return kind, outcome, f"{path}: {r.err.strip()[:300]}"

        for kind, outcome, what in self.parallel(cases, one):
            self.record("scene", kind, outcome, what)

    # ---- stage settings ----
    def configs(self):
        d = self.fresh("config")
        shutil.copy(ROOT / "data/cg.toml", d / "cg.toml")  # (piv's settings name the cg stage's, beside them)
        cases = []
        for k in range(self.counts["config"]):
            stage = self.rng.choice(STAGES)
            own = ROOT / REGISTERED[stage].config if REGISTERED[stage].config else None
            # pulloff_metrics has no settings file, bed_metrics no study constants
            study = own is None or (stage != "bed_metrics" and self.rng.random() < 0.2)
            base = ROOT / "data/study.toml" if study else own
            kind, text = mutate.mutate_toml(self.rng, base.read_text())
            path = d / f"{k:05d}_{base.name}"
            path.write_text(text, errors="surrogateescape")
            out = d / f"{k:05d}_out"
            cmd = self.stage_command(stage, self.pull, out, None if study else path, path if study else None)
            cases.append((f"{stage}{'/study' if study else ''}:{kind}", path, cmd))

        def one(case):
            kind, path, cmd = case
            r = execute(cmd, self.timeout)
            return kind, classify(r, cmd[0].name, [path]), f"{path}: {r.err.strip()[:300]}"

        for kind, outcome, what in self.parallel(cases, one):
            self.record("config", kind.split(":")[1], outcome, what)

    # ---- run files ----
    # Which consumers must refuse a mutation (the rest may accept it: they
    # need not read what changed). Every consumer opens the file with the
    # run-file reader, which checks the particles, bodies, times and every
    # dataset's shape and type on opening; a snapshot's values when it is read.
    OPENED = ("particles/", "bodies/", "snapshots/time", "snapshots/step", "series/time", "snapshots/contact_start")
    # What each consumer reads of it: a stage, what the registry says (its `reads`); dem2d --initial, the
    # last snapshot with its contacts.
    ENGINE_READS = ("last snapshot", "last contacts")

    def reads(self, consumer, what, where):
        """Whether `consumer` reads `what` ("series", "snapshots", "contacts") of a file damaged `where`."""
        declared = REGISTERED[consumer].reads if consumer in REGISTERED else self.ENGINE_READS
        last = {"snapshots": "last snapshot", "contacts": "last contacts"}.get(what)
        return what in declared or (where == "last" and last in declared)

    # Records a run file may lack (files written before they existed; the schema's optional
    # datasets): their deletion is not damage a reader must see.
    OPTIONAL = tuple(d["path"] for d in schema.schema()["datasets"] if d["optional"])

    def must_fail(self, consumer, kind, name, where):
        if kind == "root_attr":  # the format, and the counts where given (older files lack them); the rest: as
            # the readers' verdicts agree
            return name == "@format" or (name in ("@n_particles", "@n_bodies") and where != "deleted")
        if kind == "truncate_file" or where == "none":
            return kind == "truncate_file"
        structural = kind in ("shorter", "empty", "delete", "int_type", "reverse_time", "repeat_time")
        if name.startswith("series/"):  # read by the drag's consumers only
            return self.reads(consumer, "series", where) and (structural or kind in ("nan", "inf")) and \
                name in ("series/time", "series/body_force_mean", "series/body_vertices")
        if structural:
            if kind == "delete" and name.startswith(self.OPTIONAL):
                return False
            return name.startswith(self.OPENED + self.OPTIONAL) or name.startswith(("snapshots/", "contacts/"))
        if name.startswith(("particles/diameter", "particles/mass")):
            return kind != "huge"
        if name in ("snapshots/time", "series/time"):
            return kind in ("nan", "inf")
        if name in ("snapshots/position", "snapshots/velocity") and kind in ("nan", "inf"):
            return self.reads(consumer, "snapshots", where)
        if name.startswith("contacts/") and kind in ("nan", "inf", "bad_contact"):
            unread = ("contacts/mr", "contacts/mu_star", "contacts/line")  # (read by none)
            return self.reads(consumer, "contacts", where) and name not in unread
        return False

    def damaged_copy(self, path, wrong_counts=False):
        """A copy of the pull-off's run file at `path` with one mutation (mutate.mutate_run; with
        wrong_counts, 15 % of them a root count that does not match the file): (kind, dataset, where)."""
        shutil.copy(self.pull, path)
        with h5py.File(path, "r+") as f:
            if wrong_counts and self.rng.random() < 0.15:
                attr = self.rng.choice(["n_particles", "n_bodies"])
                f.attrs[attr] = int(f.attrs[attr]) + self.rng.choice([-1, 1, 95])
                kind, name, where = "attr_count", attr, "all"
            else:
                kind, name, where = mutate.mutate_run(self.rng, f)
        if kind == "truncate_file":
            with open(path, "r+b") as fh:
                fh.truncate(self.rng.randrange(path.stat().st_size))
        return kind, name, where

    def runfiles(self):
        d = self.fresh("runfile")
        cases = []
        for k in range(self.counts["runfile"]):
            path = d / f"{k:05d}.h5"
            kind, name, where = self.damaged_copy(path)
            for consumer, cmd in self.consumers(path, d / f"{k:05d}_out").items():
                cases.append((kind, name, where, consumer, path, cmd))

        def one(case):
            kind, name, where, consumer, path, cmd = case
            r = execute(cmd, self.timeout)
            program = "dem2d" if consumer == "dem2d_initial" else consumer
            outcome = classify(r, program, [path], self.must_fail(consumer, kind, name, where))
            return kind, outcome, f"{consumer} on {path} ({kind} {name} {where}): {r.err.strip()[:300]}"

        for kind, outcome, what in self.parallel(cases, one):
            self.record("runfile", kind, outcome, what)

    # ---- the two readers ----
    def must_refuse_whole(self, kind, name, where):
        """What a reader of the whole file must refuse: any damage to a record it reads."""
        if kind in ("truncate_file", "attr_count"):
            return True
        if kind == "root_attr":
            return self.must_fail("", kind, name, where)
        if where == "none" or kind in ("negative", "huge"):
            return name.startswith(("particles/diameter", "particles/mass")) and kind == "negative"
        if name.startswith(("xdmf/", "contacts/mu_star", "snapshots/displacement")):
            return False  # neither reader reads the XDMF index; NaN is allowed where nothing was recorded
        if name == "particles/inertia" and kind == "inf":
            return False  # a grain that does not rotate
        if kind == "delete":
            return not name.startswith(self.OPTIONAL + ("parameters/", "series/energy/"))
        return not name.startswith("parameters/") or kind in ("nan", "inf")

    def readers(self):
        d = self.fresh("reader")
        cases = []
        for k in range(self.counts["reader"]):
            path = d / f"{k:05d}.h5"
            cases.append((*self.damaged_copy(path, wrong_counts=True), path))
        py_reader = Path(__file__).resolve().parent / "py_reader.py"

        def one(case):
            kind, name, where, path = case
            cpp = classify(execute([self.dem2d, "inspect", path], self.timeout), "dem2d", [path])
            r = execute([sys.executable, py_reader, path], self.timeout)
            py = "traceback" if r.rc == 1 and "Traceback" in r.err else classify(r, "dem2d-python", [path])
            what = f"{path} ({kind} {name} {where}): dem2d inspect {cpp}, python {py}: {r.err.strip()[-300:]}"
            if py == "traceback" or cpp in DEFECTS or py in DEFECTS:
                return kind, py if py in DEFECTS else cpp, what
            if cpp != py:
                return kind, "disagree", what
            if cpp == "ok" and self.must_refuse_whole(kind, name, where):
                return kind, "silent", what
            return kind, cpp, what

        for kind, outcome, what in self.parallel(cases, one):
            self.record("reader", kind, outcome, what)

    # ---- faults ----
    def faults(self):
        d = self.fresh("fault")
        scene = d / "scene.toml"
        # the tiny fill with a third of its grains (100: it settles in a third of the steps) and a
        # checkpoint every 0.01 s: each case runs it once or twice, the reference once
        scene.write_text((ROOT / "tests/fuzz/tiny_fill.toml").read_text().replace(
            "checkpoint_interval = 0.05", "checkpoint_interval = 0.01").replace("count = 300", "count = 100"))
        run = [self.dem2d, "run", scene, "--threads", "1"]
        r = execute([*run, "--out", d / "ref"], self.timeout * 5)
        if r.rc != 0:
            sys.exit(f"fuzz: the fault scene failed:\n{r.err}")
        ref, wall = d / "ref/run.h5", r.seconds
        same = ROOT / "tests/tools/same_run.py"

        def identical(out):
            return execute([sys.executable, same, out / "run.h5", ref], self.timeout).rc == 0

        modes = ["KILL", "TERM", "INT", "disk", "workdir"] + (["tmpfs"] if self.can_mount(d) else [])
        for k in range(self.counts["fault"]):
            mode = self.rng.choice(modes)
            out = d / f"{k:03d}_{mode}"
            what = f"{out}"
            if mode in ("KILL", "TERM", "INT"):
                p = subprocess.Popen([str(c) for c in [*run, "--out", out]], stderr=subprocess.PIPE, text=True)
                time.sleep(self.rng.uniform(0.05, 1.1) * wall)  # the end: while the run file is assembled
                p.send_signal(getattr(signal, "SIG" + mode))
                _, err = p.communicate()
                if "runtime error:" in err or "Sanitizer" in err:
                    self.record("fault", mode, "sanitizer", f"{what}: {err[:300]}")
                    continue
                if (out / "run.h5").exists():
                    # finished before the signal, or killed after the run file's last rename
                    # (its segments not yet deleted): a run file that exists is the whole run
                    outcome = "ok" if identical(out) else "fault"
                else:
                    r = execute([*run, "--out", out], self.timeout * 5)
                    outcome = "resumed" if r.rc == 0 and identical(out) else "fault"
                    what += f": rerun exit {r.rc}: {r.err.strip()[:300]}"
            elif mode == "tmpfs":
                outcome, what = self.full_tmpfs(d / f"{k:03d}_tmpfs", run, identical)
            elif mode == "disk":
                limit = self.rng.choice([8, 30, 80, 200, 600]) * 1024

                def small_disk(limit=limit):
                    signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
                    resource.setrlimit(resource.RLIMIT_FSIZE, (limit, limit))

                r = execute([*run, "--out", out], self.timeout * 5, preexec=small_disk, env=FULL_DISK_ENV)
                if r.rc == 0:
                    outcome = "ok" if identical(out) else "fault"
                elif classify(r, "dem2d", [out]) in ("failed", "error") and not (out / "run.h5").exists():
                    r2 = execute([*run, "--out", out], self.timeout * 5)
                    outcome = "resumed" if r2.rc == 0 and identical(out) else "fault"
                    what += f": rerun exit {r2.rc}: {r2.err.strip()[:300]}"
                else:
                    outcome = classify(r, "dem2d", [out])
                    outcome = outcome if outcome in DEFECTS else "fault"
                what += f" (file size limit {limit} B): exit {r.rc}: {r.err.strip()[:300]}"
            else:
                r = execute([*run, "--out", out, "--interrupt-at-step", str(self.rng.randrange(2000, 25000))], self.timeout * 5)
                damage = self.damage(out / ".run.work")
                r = execute([*run, "--out", out], self.timeout * 5)
                if r.rc == 0:
                    outcome = "resumed" if identical(out) else "fault"
                elif "--fresh" in r.err and not (out / "run.h5").exists():
                    r2 = execute([*run, "--out", out, "--fresh"], self.timeout * 5)
                    outcome = "refused" if r2.rc == 0 and identical(out) else "fault"
                else:
                    outcome = classify(r, "dem2d", [out])
                    outcome = outcome if outcome in DEFECTS else "fault"
                what += f" ({damage}): exit {r.rc}: {r.err.strip()[:300]}"
                mode = f"workdir:{damage.split(' ')[0]}"
            self.record("fault", mode, outcome, what)

    def can_mount(self, d):
        """A real full disk needs a small tmpfs: root only (CI runs as root)."""
        probe = d / "mount_probe"
        probe.mkdir(exist_ok=True)
        ok = os.geteuid() == 0 and subprocess.run(["mount", "-t", "tmpfs", "-o", "size=64k", "tmpfs", str(probe)],
                                                  capture_output=True).returncode == 0
        if ok:
            subprocess.run(["umount", str(probe)], check=True)
        else:
            print("fuzz: NOT TESTED: a full disk on a tmpfs (needs root and mount); the file size limit stands in")
        return ok

    def full_tmpfs(self, mnt, run, identical):
        """The run on a tmpfs too small for it: a clean failure and no run file;
        then the same tmpfs grown and the run resumed."""
        size = self.rng.choice([48, 120, 300, 800])
        mnt.mkdir()
        subprocess.run(["mount", "-t", "tmpfs", "-o", f"size={size}k", "tmpfs", str(mnt)], check=True)
        try:
            out = mnt / "out"
            r = execute([*run, "--out", out], self.timeout * 5, env=FULL_DISK_ENV)
            what = f"{mnt} ({size} KiB): exit {r.rc}: {r.err.strip()[:300]}"
            if r.rc == 0:
                return ("ok" if identical(out) else "fault"), what
            outcome = classify(r, "dem2d", [out])
            if outcome not in ("failed", "error") or (out / "run.h5").exists():
                return (outcome if outcome in DEFECTS else "fault"), what
            subprocess.run(["mount", "-o", "remount,size=64m", str(mnt)], check=True)
            r2 = execute([*run, "--out", out], self.timeout * 5)
            ok = r2.rc == 0 and identical(out)
            return ("resumed" if ok else "fault"), what + f"; grown: exit {r2.rc}: {r2.err.strip()[:300]}"
        finally:
            subprocess.run(["umount", str(mnt)], check=False)

    def damage(self, work):
        """Damages an unfinished run's work directory; returns what was done."""
        files = sorted(work.glob("*.h5"))
        if not files:
            return "none (no work directory)"
        kind = self.rng.choice(["truncate", "garbage", "delete", "nan"])
        victim = self.rng.choice(files)
        if kind == "truncate":
            size = victim.stat().st_size
            with open(victim, "r+b") as f:
                f.truncate(self.rng.randrange(size))
        elif kind == "garbage":
            with open(victim, "r+b") as f:
                f.seek(self.rng.randrange(victim.stat().st_size))
                f.write(bytes(self.rng.randrange(256) for _ in range(64)))
        elif kind == "delete":
            victim.unlink()
        else:
            with h5py.File(victim, "r+") as f:
                names = mutate.float_datasets(f)
                name = self.rng.choice(names)
                data = f[name][...]
                data.reshape(-1)[self.rng.randrange(data.size)] = float("nan")
                f[name][...] = data
        return f"{kind} {victim.name}"

    def report(self, seconds):
        outcomes = ["ok", "error", "failed", "resumed", "refused", "skipped", *DEFECTS]
        print(f"fuzz: {self.bin} ({seconds:.0f} s)")
        print(f"{'class':8} {'kind':22} {'inputs':>6} " + " ".join(f"{o:>9}" for o in outcomes))
        total = collections.Counter()
        for (cls, kind), c in sorted(self.table.items()):
            total.update(c)
            print(f"{cls:8} {kind:22} {sum(c.values()):6} " + " ".join(f"{c[o]:9}" for o in outcomes))
        print(f"{'all':8} {'':22} {sum(total.values()):6} " + " ".join(f"{total[o]:9}" for o in outcomes))
        for f in self.failures[:20]:
            print("failed (exit 1)", f)
        for d in self.defects:
            print("DEFECT", d)
        print(f"fuzz: {len(self.defects)} defects")
        return 1 if self.defects else 0


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--bin", required=True, help="build tree with sim/dem2d and analysis/")
    ap.add_argument("--quick", action="store_true", help="the short version (make test)")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--work", default=None, help="working folder (default: a temporary one)")
    ap.add_argument("--only", default=",".join(CLASSES), help=f"classes, of: {','.join(CLASSES)}")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--setup-only", action="store_true",
                    help="make the valid base (WORK/base) and stop: the fixture the classes' tests share")
    ap.add_argument("--base", default=None, help="a valid base made by --setup-only, instead of making one")
    ap.add_argument("--counts", default="", metavar="CLASS=N,...",
                    help="cases per class instead of the version's (the ASan+UBSan build's shorter sample)")
    args = ap.parse_args()
    if args.setup_only and args.work is None:
        ap.error("--setup-only needs --work DIR (the base is left in DIR/base)")
    tmp = None
    if args.work is None:
        tmp = tempfile.TemporaryDirectory(prefix="dem2d_fuzz_")
        args.work = tmp.name
    t0 = time.monotonic()
    suite = Suite(args)
    suite.setup(args.base)
    if args.setup_only:
        print(f"fuzz: the valid base is in {Path(args.work) / 'base'}")
        return 0
    classes = args.only.split(",")
    unknown = [c for c in classes if c not in CLASSES]
    if unknown:
        ap.error(f"--only {args.only}: unknown class {unknown[0]!r} (allowed: {', '.join(CLASSES)})")
    for cls in classes:
        {"scene": suite.scenes, "config": suite.configs, "runfile": suite.runfiles, "reader": suite.readers,
         "fault": suite.faults, "pipeline": Pipeline(suite).run, "install": Install(suite).run,
         "paths": Paths(suite).run,
         "slurm": Cluster(suite).run}[cls]()
    rc = suite.report(time.monotonic() - t0)
    if tmp:
        tmp.cleanup()
    return rc


if __name__ == "__main__":
    sys.exit(main())
