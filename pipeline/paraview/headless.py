"""Runs a command (pvbatch, pvpython) on an X server of its own: Debian's ParaView 5.11
renders only through X (its VTK has neither OSMesa nor EGL), so without a display

    python3 pipeline/paraview/headless.py pvbatch SCRIPT.py ARGS...

starts Xvfb (Debian: xvfb), which picks a free display itself (-displayfd) and names it
once it accepts connections, runs the command on it with a private cookie, then stops
that Xvfb (by its PID; it also ends with this process). Exits with the command's status.

The server never resets (-noreset). By default Xvfb resets whenever its last client
disconnects, and pvbatch connects once and disconnects before it opens its render
window: on a loaded machine that second connection met the reset and failed ("bad X
server connection", SIGABRT: 54 of 60 renders failed with 20 at once on 2 cores).
With -noreset: 0 of 40. The display number needs no guess (no race on :99).

Without Xvfb, the command runs on $DISPLAY if there is one, else this says what is missing.

A script imports require_display() to fail with a message, not a SIGSEGV, without a display.
"""
import ctypes
import os
import secrets
import select
import shutil
import signal
import socket
import struct
import subprocess
import sys
import tempfile

SCREEN = "1280x1024x24"  # 24 bits: the default 8 may have no OpenGL visual
START_TIMEOUT = 120.0  # s, for Xvfb to accept connections (a loaded machine)


def require_display(prog):
    """Exits with a message unless an X display can be opened (rendering would crash)."""
    try:
        x11 = ctypes.CDLL("libX11.so.6")
        x11.XOpenDisplay.restype = ctypes.c_void_p
        x11.XCloseDisplay.argtypes = [ctypes.c_void_p]
        d = x11.XOpenDisplay(None) if os.environ.get("DISPLAY") else None
    except OSError:
        d = None
    if not d:
        sys.exit(f"{prog}: cannot open an X display (DISPLAY={os.environ.get('DISPLAY', '')!r}): ParaView renders "
                 f"only through X here; run it as python3 pipeline/paraview/headless.py pvbatch ...")
    x11.XCloseDisplay(d)


def xauthority(path, cookie):
    """An Xauthority file with one MIT-MAGIC-COOKIE-1 for any host and display (FamilyWild,
    no display number): the server reads it with -auth, the command with XAUTHORITY."""
    def field(b):
        return struct.pack(">H", len(b)) + b
    entry = struct.pack(">H", 0xFFFF) + field(socket.gethostname().encode()) + field(b"") + \
        field(b"MIT-MAGIC-COOKIE-1") + field(cookie)
    fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600)
    with os.fdopen(fd, "wb") as f:
        f.write(entry)


def die_with_parent():
    """In the child: SIGTERM when this process ends, however it ends (Linux)."""
    try:
        ctypes.CDLL(None, use_errno=True).prctl(1, signal.SIGTERM)  # PR_SET_PDEATHSIG
    except (OSError, AttributeError):
        pass


def start_xvfb(xvfb, work):
    """Xvfb on a display it chooses: (process, ":N", its Xauthority file)."""
    auth = os.path.join(work, "Xauthority")
    xauthority(auth, secrets.token_bytes(16))
    read_end, write_end = os.pipe()
    log = open(os.path.join(work, "xvfb.log"), "wb")
    try:
        proc = subprocess.Popen([xvfb, "-displayfd", str(write_end), "-screen", "0", SCREEN, "-nolisten", "tcp",
                                 "-noreset", "-auth", auth], stdin=subprocess.DEVNULL, stdout=log, stderr=log,
                                pass_fds=(write_end,), preexec_fn=die_with_parent)
    finally:
        os.close(write_end)
        log.close()
    number = b""
    try:
        while not number.endswith(b"\n"):
            ready, _, _ = select.select([read_end], [], [], START_TIMEOUT)
            chunk = os.read(read_end, 32) if ready else b""
            if not chunk:  # Xvfb ended, or took too long
                break
            number += chunk
    finally:
        os.close(read_end)
    if not number.strip().isdigit():
        stop(proc)
        with open(os.path.join(work, "xvfb.log"), errors="replace") as f:
            tail = f.read()[-2000:]
        sys.exit(f"headless: Xvfb did not start (exit {proc.returncode}):\n{tail}")
    return proc, ":" + number.strip().decode(), auth


def stop(proc):
    if proc.poll() is None:
        proc.terminate()
        try:
            proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()


def main():
    cmd = sys.argv[1:]
    if not cmd or cmd[0] in ("-h", "--help"):
        sys.exit(__doc__)
    xvfb = shutil.which("Xvfb")
    if xvfb is None:
        if not os.environ.get("DISPLAY"):
            sys.exit("headless: no X display and no Xvfb (Debian: apt-get install xvfb): ParaView 5.11 renders only "
                     "through X")
        os.execvp(cmd[0], cmd)
    # SIGTERM, SIGHUP: through the finally below (the command and Xvfb stopped)
    for s in (signal.SIGTERM, signal.SIGHUP):
        signal.signal(s, lambda signum, frame: sys.exit(128 + signum))
    with tempfile.TemporaryDirectory(prefix="dem2d-xvfb-") as work:
        server, display, auth = start_xvfb(xvfb, work)
        child = None
        try:
            env = dict(os.environ, DISPLAY=display, XAUTHORITY=auth)
            # pvbatch's MPI (hwloc) opens every X display it finds, other users' too, to look
            # for GPUs; that finds none here and only adds "Invalid MIT-MAGIC-COOKIE-1 key" lines
            env.setdefault("HWLOC_COMPONENTS", "-gl")
            try:
                child = subprocess.Popen(cmd, env=env, preexec_fn=die_with_parent)
            except OSError as e:
                sys.exit(f"headless: {cmd[0]}: {e.strerror}")
            code = child.wait()
        finally:
            if child is not None:
                stop(child)
            stop(server)
    sys.exit(code if code >= 0 else 128 - code)


if __name__ == "__main__":
    main()
