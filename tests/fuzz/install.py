"""make fuzz's class `install` (tests/fuzz/fuzz.py): the installed programs
(cmake --install of the build under test) with their share/ moved, deleted,
another installation's share/ above the prefix or in the current folder,
DEM2D_SHARE naming a good, missing, empty or file path, the program reached
through a link or copied elsewhere. A program runs with its own share/dem2d
(or the one DEM2D_SHARE names) or stops with exit 2 naming DEM2D_SHARE:
never with another installation's data (`foreign`: dem2d's run file stamped
with the other code version, a stage reading the other settings)."""
import os
import shutil
import subprocess
import sys
from pathlib import Path

import h5py

from outcomes import classify, execute

ROOT = Path(__file__).resolve().parent.parent.parent
LAYOUTS = ("intact", "relocated", "share_moved", "data_deleted", "foreign_parent", "foreign_cwd", "foreign_beside",
           "env_named", "env_missing", "env_empty_dir", "env_file", "env_empty_string", "bin_link", "copied_binary")
OWN = ("intact", "relocated", "foreign_beside", "env_empty_string", "bin_link")  # run with their own share


class Install:
    def __init__(self, suite):
        self.s = suite
        self.rng = suite.rng

    def run(self):
        d = self.s.fresh("install")
        self.prefix = d / "prefix"
        r = subprocess.run(["cmake", "--install", str(self.s.bin), "--prefix", str(self.prefix)], capture_output=True,
                           text=True)
        if r.returncode != 0:
            sys.exit(f"fuzz: cmake --install {self.s.bin} failed:\n{r.stdout[-2000:]}{r.stderr[-2000:]}")
        self.own_version = (self.prefix / "share/dem2d/code_version.txt").read_text().strip()  # (stamped X.Y.Z+it)
        for k in range(self.s.counts["install"]):
            layout = self.rng.choice(LAYOUTS)
            program = self.rng.choice(["dem2d", "spectrum"])
            outcome, what = self.trial(d / f"{k:04d}", layout, program)
            self.s.record("install", f"{layout}:{program}", outcome, what)

    def foreign_share(self, at: Path, version: str, poisoned: bool):
        """Another installation's share/dem2d at `at`: another code version, and (poisoned) settings no
        stage accepts, so a stage that reads them says so."""
        shutil.copytree(self.prefix / "share/dem2d", at)
        (at / "code_version.txt").write_text(version + "\n")
        if poisoned:
            (at / "data/spectrum.toml").write_text("FOREIGN_SETTINGS = [\n")

    def trial(self, case, layout, program):
        prefix = case / "prefix"
        shutil.copytree(self.prefix, prefix, symlinks=True)
        cwd = case / "cwd"
        cwd.mkdir()
        env = {k: v for k, v in os.environ.items() if k != "DEM2D_SHARE"}
        version = self.own_version
        exe_dir = {"dem2d": prefix / "bin", "spectrum": prefix / "libexec/dem2d"}[program]
        exe = exe_dir / program
        if layout == "relocated":
            prefix = prefix.rename(case / "moved")
            exe = (prefix / "bin" if program == "dem2d" else prefix / "libexec/dem2d") / program
        elif layout == "share_moved":
            (prefix / "share").rename(case / "share.away")
        elif layout == "data_deleted":
            shutil.rmtree(prefix / "share/dem2d/data")
        elif layout == "foreign_parent":
            shutil.rmtree(prefix / "share")
            self.foreign_share(case / "share/dem2d", "foreign-parent", True)
        elif layout == "foreign_cwd":
            shutil.rmtree(prefix / "share")
            self.foreign_share(cwd / "share/dem2d", "foreign-cwd", True)
        elif layout == "foreign_beside":
            self.foreign_share(case / "share/dem2d", "foreign-beside", True)
            self.foreign_share(cwd / "share/dem2d", "foreign-beside", True)
        elif layout == "env_named":
            self.foreign_share(case / "named/dem2d", "named-share", False)
            env["DEM2D_SHARE"], version = str(case / "named/dem2d"), "named-share"
        elif layout == "env_missing":
            env["DEM2D_SHARE"] = str(case / "no_such")
        elif layout == "env_empty_dir":
            (case / "empty").mkdir()
            env["DEM2D_SHARE"] = str(case / "empty")
        elif layout == "env_file":
            (case / "a_file").write_text("x\n")
            env["DEM2D_SHARE"] = str(case / "a_file")
        elif layout == "env_empty_string":
            env["DEM2D_SHARE"] = ""
        elif layout == "bin_link":
            (case / "links").mkdir()
            (case / "links" / program).symlink_to(exe)
            exe = case / "links" / program
        elif layout == "copied_binary":
            (case / "elsewhere/bin").mkdir(parents=True)
            exe = Path(shutil.copy2(exe, case / "elsewhere/bin" / program))
            self.foreign_share(case / "share/dem2d", "foreign-parent", True)
        out = case / "out"
        if program == "dem2d":
            cmd = [exe, "run", ROOT / "tests/scenes/valid_minimal.toml", "--out", out, "--threads", "1"]
        else:
            cmd = [exe, self.s.pull, "--out", out]
        r = execute(cmd, self.s.timeout, env=env, cwd=cwd)
        what = f"{layout}: {' '.join(map(str, cmd))}: exit {r.rc}: {r.err.strip()[:300]}"
        outcome = classify(r, program, [])
        if "FOREIGN_SETTINGS" in r.err:
            return "foreign", what + " (another installation's settings were read)"
        if program == "dem2d" and (out / "run.h5").exists():
            with h5py.File(out / "run.h5", "r") as f:
                stamped = str(f.attrs["code_version"])
            if stamped.partition("+")[2] != version:
                return "foreign", what + f" (run file stamped {stamped!r}, not {version!r})"
        if outcome in ("hang", "crash", "sanitizer"):
            return outcome, what
        if layout in OWN or layout == "env_named":
            return ("ok" if r.rc == 0 else "fault"), what + ("" if r.rc == 0 else " (refused with its share)")
        if r.rc == 0:
            return "silent", what + " (ran without its share)"
        return ("error" if r.rc == 2 and "DEM2D_SHARE" in r.err and len(r.err) <= 4000 else "message"), what
