"""make fuzz's class `slurm` (tests/fuzz/fuzz.py): quick ensembles (1 or 2
members) through a real one-node Slurm (pipeline/slurm/local_cluster.sh,
started here and stopped by its PIDs; root only, said loudly otherwise),
with these faults in turn:

  none            every member and the aggregate succeed: exit 0, stats.json
  failing_member  one member's overlay is broken: its task fails
  lost_node       slurmd and the member's processes are killed under it
  cancelled       the array job is cancelled (scancel) while it runs
  resubmit        a second submission into the same folder while the first
                  is listed: refused; the first then succeeds
  controller_lost slurmctld killed while a member runs: the wait goes on to
                  its bound, then names what did not finish as "not finished
                  when the controller stopped answering" (never "never ran",
                  never done)

A submission with a fault must end non-zero naming each member that did not
finish (`silent` if it exits 0, `message` if it does not name them), within
its wait bound (`hang`); a refused resubmission must say why."""
import os
import signal
import subprocess
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent.parent
FAULTS = ("none", "failing_member", "lost_node", "cancelled", "resubmit", "controller_lost")
LIMIT = 1200.0  # s for one ensemble of the quick scene through the cluster


class Cluster:
    def __init__(self, suite):
        self.s = suite
        self.rng = suite.rng

    def run(self):
        n = self.s.counts["slurm"]
        if n == 0:
            return
        if os.geteuid() != 0 or subprocess.run(["sh", "-c", "command -v slurmctld slurmd munged"],
                                               capture_output=True).returncode != 0:
            print("fuzz: NOT TESTED: class slurm needs root and Debian's slurm-wlm and munge "
                  "(make test-cluster installs them)")
            self.s.record("slurm", "not tested", "skipped", "no root or no Slurm")
            return
        d = self.s.fresh("slurm")
        self.base, self.clusters = d, 0
        try:
            self.start()
            for k in range(n):
                fault = FAULTS[k % len(FAULTS)]  # every fault once in six trials
                outcome, what = self.trial(d / f"{k:03d}", fault, self.rng.choice([1, 2]))
                self.s.record("slurm", fault, outcome, what)
        finally:
            self.stop()

    def start(self):
        """A cluster in a folder of its own: one restarted on the state of a lost node would still list
        the lost job, its node not idle."""
        self.clusters += 1
        self.dir = self.base / f"cluster{self.clusters}"
        for attempt in range(2):  # (a node still finishing a killed job's steps is not idle at once)
            r = subprocess.run([str(ROOT / "pipeline/slurm/local_cluster.sh"), "start", str(self.dir)],
                               capture_output=True, text=True)
            if r.returncode == 0:
                break
            self.stop()
            time.sleep(30)
        if r.returncode != 0:
            raise SystemExit(f"fuzz: the one-node cluster did not start:\n{r.stdout[-1500:]}{r.stderr[-1500:]}")
        os.environ["SLURM_CONF"] = str(self.dir / "slurm.conf")

    def stop(self):
        subprocess.run([str(ROOT / "pipeline/slurm/local_cluster.sh"), "stop", str(self.dir)], capture_output=True)

    def submit(self, results, members, extra_env=None):
        env = dict(os.environ, SLURM_WAIT_MINUTES="3", SLURM_POLL_SECONDS="2", **(extra_env or {}))
        return subprocess.Popen(["make", "--no-print-directory", "-C", str(ROOT), "ensemble", "PRESET=quick",
                                 f"MEMBERS={members}", f"RESULTS={results}", "EXECUTOR=slurm", "SLURM_WAIT=1"],
                                stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, env=env)

    def trial(self, case, fault, members):
        ensemble = case / "ensemble"
        victim = self.rng.randrange(members)
        name = f"member_{victim:03d}"
        if fault == "failing_member":
            (ensemble / name).mkdir(parents=True)
            (ensemble / name / "member.toml").write_text("[time]\nnot_a_key = 1\n")  # newer than what makes it
        p = self.submit(case, members)
        second = None
        if fault in ("lost_node", "cancelled", "resubmit", "controller_lost"):
            started = self.wait_for(ensemble / name / "fill/run.log", p)
            if started and fault == "lost_node":
                self.kill_node(ensemble)
            elif started and fault == "controller_lost":
                os.kill(int((self.dir / "slurmctld.pid").read_text()), signal.SIGKILL)
            elif started and fault == "cancelled":
                subprocess.run(["scancel", *(ensemble / "slurm/jobs").read_text().split()], capture_output=True)
            elif started:
                second = subprocess.run(["make", "--no-print-directory", "-C", str(ROOT), "ensemble", "PRESET=quick",
                                         f"MEMBERS={members}", f"RESULTS={case}", "EXECUTOR=slurm"],
                                        capture_output=True, text=True, timeout=120)
        try:
            log, _ = p.communicate(timeout=LIMIT)
        except subprocess.TimeoutExpired:
            p.kill()
            return "hang", f"{case} ({fault}): no end in {LIMIT:.0f} s"
        finally:
            if fault in ("lost_node", "controller_lost"):
                if fault == "controller_lost" and (ensemble / "slurm/jobs").exists():
                    self.kill_node(ensemble)  # (the jobs slurmd still runs)
                self.stop()
                self.start()
        what = f"{case} ({fault}, {members} members, {name}): exit {p.returncode}: {log.strip()[-400:]}"
        if fault in ("none", "resubmit"):
            if second is not None and (second.returncode == 0 or "still queued or running" not in second.stderr):
                return "silent", what + f"; the resubmission: exit {second.returncode}: {second.stderr[-300:]}"
            ok = p.returncode == 0 and (ensemble / "stats.json").exists()
            return ("ok" if ok else "fault"), what
        if p.returncode == 0:
            return "silent", what
        if fault == "controller_lost":
            said = "not finished when the controller stopped answering" in log and "never ran" not in log
            return ("failed" if said and ", done" not in log else "message"), what
        if ", done" in log or f"{name}/metrics.json" not in log:
            return "message", what
        return "failed", what

    def wait_for(self, path, p, seconds=300):
        t0 = time.monotonic()
        while time.monotonic() - t0 < seconds and p.poll() is None:
            if path.exists():
                return True
            time.sleep(0.5)
        return False

    def kill_node(self, ensemble):
        """slurmd and every process of the ensemble's jobs killed, as when a node dies."""
        jobs = (ensemble / "slurm/jobs").read_text().split()
        os.kill(int((self.dir / "slurmd.pid").read_text()), signal.SIGKILL)
        steps = subprocess.run(["pgrep", "-f", "^slurmstepd: \\[(" + "|".join(jobs) + ")[._]"],
                               capture_output=True, text=True).stdout.split()
        for pid in steps:
            for child in self.descendants(pid) + [pid]:
                try:
                    os.kill(int(child), signal.SIGKILL)
                except ProcessLookupError:
                    pass

    def descendants(self, pid):
        kids = subprocess.run(["pgrep", "-P", str(pid)], capture_output=True, text=True).stdout.split()
        return [g for k in kids for g in self.descendants(k)] + kids
