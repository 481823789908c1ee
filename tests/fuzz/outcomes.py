"""What one program run came to (tests/fuzz/fuzz.py): its exit, its message, and
the outcome classes every class of the suite shares (docs/fuzz.md, "Outcomes")."""
import subprocess
import time
from pathlib import Path

# crash: a signal or another exit code; sanitizer: an ASan/UBSan report; hang: no exit in time; message:
# exit 2 not naming the input, or too long; disagree: two programs' verdicts differ; traceback: a Python
# tool's own exception; silent: exit 0 on an input that must be refused; fault: a wrong result or file;
# ran: text from an input ran as a command, or changed the Makefile's own variables or targets;
# destroyed: a user's file replaced, changed or deleted; foreign: another installation's data used,
# or a file written outside the output folder
DEFECTS = ("crash", "sanitizer", "hang", "message", "disagree", "traceback", "silent", "fault", "ran",
           "destroyed", "foreign")


class Result:
    def __init__(self, rc, err, seconds, out=""):
        self.rc, self.err, self.seconds, self.out = rc, err, seconds, out


def execute(cmd, timeout, preexec=None, env=None, cwd=None):
    t0 = time.monotonic()
    try:
        p = subprocess.run([str(c) for c in cmd], capture_output=True, text=True, errors="replace",
                           timeout=timeout, preexec_fn=preexec, env=env, cwd=cwd)
        return Result(p.returncode, p.stderr, time.monotonic() - t0, p.stdout)
    except subprocess.TimeoutExpired as e:
        err = e.stderr.decode(errors="replace") if isinstance(e.stderr, bytes) else (e.stderr or "")
        return Result(None, err, time.monotonic() - t0)


def classify(r, program, names, must_fail=False):
    """The outcome of one run: `names` are the input files one of which a
    bad-input message must name (by path or file name)."""
    if r.rc is None:
        return "hang"
    if "runtime error:" in r.err or "Sanitizer" in r.err:
        return "sanitizer"
    if r.rc < 0 or r.rc not in (0, 1, 2, 3):
        return "crash"
    if r.rc == 0:
        return "silent" if must_fail else "ok"
    # (progress lines, "[dem2d] ...", may come before the message)
    lines = [line for line in r.err.strip().splitlines() if not line.startswith("[dem2d] ")]
    first = lines[0] if lines else ""
    sane = first.startswith(f"{program}: ") and len(r.err) <= 4000
    if r.rc == 2:
        named = any(str(n) in r.err or Path(n).name in r.err for n in names)
        return "error" if sane and named else "message"
    return "failed" if sane else "message"
