"""ParaView (Debian's python3-paraview) and run.xdmf: both Xdmf3 readers give the
particles, bodies and contacts of every snapshot of the examples' runs; the recipe of
docs/run_file.md, run as the page gives it, and the paper's Fig. 6b view
(pipeline/paraview/force_network.py) render the example pull-off with either reader.
What ParaView read is checked against the run file (h5py), and the pictures are not
empty. Rendering goes through pipeline/paraview/headless.py (an Xvfb of its own)."""
import ast
import os
import re
import shutil
import subprocess
import sys

import h5py
import matplotlib.image
import numpy as np
import pytest

from conftest import REPO

PVBATCH = shutil.which("pvbatch")
PARAVIEW = os.path.join(REPO, "pipeline", "paraview")
PARTS = ("particles", "bodies", "contacts")
pytestmark = pytest.mark.skipif(PVBATCH is None, reason="NOT RUN: ParaView's pvbatch is missing (Debian: python3-paraview)")


def pvbatch(args, render=True, cwd=None):
    """pvbatch ARGS; on an X server of its own when it renders."""
    cmd = [PVBATCH, *args]
    if render:
        if not shutil.which("Xvfb") and not os.environ.get("DISPLAY"):
            pytest.skip("NOT RUN: no display and no Xvfb (Debian: xvfb) for ParaView")
        cmd = [sys.executable, os.path.join(PARAVIEW, "headless.py"), *cmd]
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=600, cwd=cwd)
    assert r.returncode == 0, r.stdout + r.stderr
    return r.stdout


def expected_parts(h5, k):
    """(points, cells) of each part of snapshot k in run.xdmf, from the run file."""
    with h5py.File(h5, "r") as f:
        _, B, K, _ = f["snapshots/body_vertices"].shape
        N = f["particles/diameter"].shape[0]
        start = f["snapshots/contact_start"][...]
    C = int(start[k + 1] - start[k])
    return {"particles": (N, N), "bodies": (B * K, B), "contacts": (2 * C, C)}


def parts_found(out, prefix):
    """{part: (points, cells)} from lines 'PREFIX: part: P points, C cells'."""
    found = {m[1]: (int(m[2]), int(m[3])) for m in re.finditer(rf"^{prefix}: (\w+): (\d+) points, (\d+) cells", out, re.M)}
    assert set(found) == set(PARTS), out
    return found


def top_blocks(out, prefix):
    m = re.search(rf"^{prefix}: \w+: top blocks (\[.*\])$", out, re.M)
    assert m, out
    return ast.literal_eval(m[1])


def names_expected(reader, parts):
    """Xdmf3ReaderT names the blocks (no contacts block without contacts); Xdmf3ReaderS
    reads the grids as the unnamed pieces of one dataset."""
    if reader == "Xdmf3ReaderT":
        return [p for p in PARTS if parts[p][1] > 0 or p == "particles"]
    return [""]


def picture(png, shape):
    image = matplotlib.image.imread(png)[:, :, :3]
    assert image.shape[:2] == shape
    grey = (np.ptp(image, axis=2) < 0.05) & (image.max(axis=2) > 0.5) & (image.max(axis=2) < 0.95)
    colour = np.ptp(image, axis=2) > 0.3  # the bodies' blue, the chains' colour map
    return image, grey.mean(), colour.mean()


# Two clients in turn on headless.py's X server: an atom the first one made is still there
# for the second, so the server did not reset when the first left (Xvfb's default would: a
# pvbatch connecting meanwhile fails with "bad X server connection").
OUTLIVES = r"""
import ctypes, time
x11 = ctypes.CDLL("libX11.so.6")
x11.XOpenDisplay.restype = ctypes.c_void_p
x11.XCloseDisplay.argtypes = [ctypes.c_void_p]
x11.XInternAtom.argtypes = [ctypes.c_void_p, ctypes.c_char_p, ctypes.c_int]
x11.XInternAtom.restype = ctypes.c_ulong
name = b"DEM2D_OUTLIVES_ITS_CLIENTS"
d = x11.XOpenDisplay(None); made = x11.XInternAtom(d, name, 0); x11.XCloseDisplay(d)
time.sleep(0.5)
d = x11.XOpenDisplay(None); found = x11.XInternAtom(d, name, 1); x11.XCloseDisplay(d)
print(made, found)
"""


def test_the_x_server_outlives_its_clients(tmp_path):
    if not shutil.which("Xvfb"):
        pytest.skip("NOT RUN: no Xvfb (Debian: xvfb)")
    script = tmp_path / "outlives.py"
    script.write_text(OUTLIVES)
    r = subprocess.run([sys.executable, os.path.join(PARAVIEW, "headless.py"), sys.executable, str(script)],
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stdout + r.stderr
    made, found = (int(v) for v in r.stdout.split())
    assert made > 0 and found == made, "the X server reset when its first client left"


# Reading needs no display: every snapshot of every example, both readers.
CHECK_ALL = r"""
import sys
import h5py
from paraview import simple as pv
OWN = {"particles": ["POINTS", "diameter"], "bodies": ["CELLS", "thickness"], "contacts": ["CELLS", "fn"]}
for xdmf in sys.argv[1:]:
    with h5py.File(xdmf[:-len("xdmf")] + "h5", "r") as f:
        times = f["snapshots/time"][...]
    for name in ("Xdmf3ReaderS", "Xdmf3ReaderT"):
        reader = getattr(pv, name)(FileName=[xdmf])
        reader.UpdatePipelineInformation()
        assert list(reader.TimestepValues) == list(times), (xdmf, name)
        parts = {p: pv.ExtractBlock(Input=reader, Selectors=["/Root/" + p]) if name == "Xdmf3ReaderT" else
                 pv.Threshold(Input=reader, Scalars=OWN[p], LowerThreshold=-1e300, UpperThreshold=1e300) for p in OWN}
        for k, t in enumerate(times):
            for p, source in parts.items():
                source.UpdatePipeline(t)
                info = source.GetDataInformation()
                print(f"{xdmf} {name} {k} {p} {info.GetNumberOfPoints()} {info.GetNumberOfCells()}")
"""


def test_both_readers_read_every_snapshot(example_runs, tmp_path):
    script = tmp_path / "check_all.py"
    script.write_text(CHECK_ALL)
    xdmfs = [os.path.splitext(h5)[0] + ".xdmf" for h5 in example_runs.values()]
    out = pvbatch([str(script), *xdmfs], render=False)
    seen = {}
    for xdmf, reader, k, part, points, cells in (line.split() for line in out.splitlines() if line.startswith("/")):
        seen[(xdmf, reader, int(k), part)] = (int(points), int(cells))
    for xdmf in xdmfs:
        with h5py.File(xdmf[:-4] + "h5", "r") as f:
            S = f["snapshots/time"].shape[0]
        assert S > 0
        for k in range(S):
            expected = expected_parts(xdmf[:-4] + "h5", k)
            for reader in ("Xdmf3ReaderS", "Xdmf3ReaderT"):
                for part in PARTS:
                    assert seen.get((xdmf, reader, k, part)) == expected[part], (xdmf, reader, k, part)


def recipe():
    """The pvpython block of docs/run_file.md's section "ParaView: run.xdmf"."""
    with open(os.path.join(REPO, "docs", "run_file.md")) as f:
        text = f.read()
    section = text[text.index("## ParaView: run.xdmf"):]
    section = section[:section.index("\n## ", 1)]
    blocks = re.findall(r"```python\n(.*?)```", section, re.S)
    assert len(blocks) == 1, "docs/run_file.md: the ParaView section has one python block"
    return blocks[0]


# what the test adds after the recipe: what its part() gave at the view's time
REPORT = r"""
reader.UpdatePipeline(view.ViewTime)
data = servermanager.Fetch(reader)
names = [data.GetMetaData(i).Get(data.NAME()) if data.HasMetaData(i) and data.GetMetaData(i).Has(data.NAME())
         else "" for i in range(data.GetNumberOfBlocks())]
print(f"recipe: {reader.GetXMLName()}: top blocks {names}")
for name in ("particles", "bodies", "contacts"):
    source = part(name)
    source.UpdatePipeline(view.ViewTime)
    info = source.GetDataInformation()
    print(f"recipe: {name}: {info.GetNumberOfPoints()} points, {info.GetNumberOfCells()} cells")
"""


@pytest.mark.parametrize("reader", ["OpenDataFile", "Xdmf3ReaderT"])
def test_the_documented_recipe(example_runs, tmp_path, reader):
    code = recipe()
    h5 = example_runs["pulloff"]
    xdmf = os.path.splitext(h5)[0] + ".xdmf"
    assert code.count('"out/run.xdmf"') == 1 and code.count("reader = OpenDataFile(xdmf)") == 1, code
    code = code.replace('"out/run.xdmf"', repr(xdmf))
    if reader != "OpenDataFile":
        code = code.replace("reader = OpenDataFile(xdmf)", f"reader = {reader}(FileName=[xdmf])")
    script = tmp_path / "recipe.py"
    script.write_text(code + REPORT)
    out = pvbatch([str(script)], cwd=tmp_path)

    with h5py.File(h5, "r") as f:
        last = f["snapshots/time"].shape[0] - 1
    expected = expected_parts(h5, last)
    name = top_blocks(out, "recipe")
    chosen = re.search(r"^recipe: (\w+): top blocks", out, re.M)[1]
    assert chosen == ("Xdmf3ReaderS" if reader == "OpenDataFile" else reader)  # what the page says
    assert name == names_expected(chosen, expected), out
    assert parts_found(out, "recipe") == expected, out
    image, grains, colour = picture(tmp_path / "network.png", (800, 800))
    assert grains > 0.03, f"no grains drawn ({grains:.4f} of the pixels)"
    assert colour > 0.005, f"no bodies or force chains drawn ({colour:.4f} of the pixels)"


@pytest.mark.parametrize("reader", ["T", "S"])
def test_force_network(example_runs, tmp_path, reader):
    png = tmp_path / "force_network.png"
    h5 = example_runs["pulloff"]
    out = pvbatch([os.path.join(PARAVIEW, "force_network.py"), os.path.dirname(h5), str(png),
                   "--height-mm", "15", "--size", "600", "700", "--reader", reader])
    m = re.search(r"snapshot (\d+) \(H = ([\d.]+) mm.*: (\d+) contacts with F_n > 0 drawn \(run file: (\d+)\)", out)
    assert m, out
    k = int(m[1])
    assert abs(float(m[2]) - 15.0) < 1.0 and int(m[3]) == int(m[4]) > 100
    with h5py.File(h5, "r") as f:
        start = f["snapshots/contact_start"][k:k + 2]
        assert int(m[4]) == int((f["contacts/fn"][start[0]:start[1]] > 0).sum())
    expected = expected_parts(h5, k)
    assert top_blocks(out, "force_network") == names_expected("Xdmf3Reader" + reader, expected), out
    assert parts_found(out, "force_network") == expected, out
    image, grains, colour = picture(png, (700, 600))
    ink = (image < 0.95).any(axis=2)
    assert ink.mean() > 0.2, "the picture is mostly blank"
    assert grains > 0.1, f"no grains drawn ({grains:.4f} of the pixels)"
    dark = (image.max(axis=2) < 0.25).mean()  # the strongest chains (inferno's dark end)
    assert dark > 0.001, f"no strong force chain drawn ({dark:.4f} of the pixels)"


def test_force_network_writes_nothing_when_it_draws_other_data(example_runs, tmp_path):
    """run.xdmf's fn pointing at the contacts' overlaps (as many, all positive): the counts agree, the
    values do not; the script fails naming them, and leaves no picture for make to take as done."""
    h5 = example_runs["pulloff"]
    run = tmp_path / "run"
    run.mkdir()
    os.symlink(h5, run / "run.h5")
    xdmf = open(os.path.join(os.path.dirname(h5), "run.xdmf")).read()
    assert "run.h5:/contacts/fn|" in xdmf
    (run / "run.xdmf").write_text(xdmf.replace("run.h5:/contacts/fn|", "run.h5:/contacts/overlap|"))
    png = tmp_path / "force_network.png"
    if not shutil.which("Xvfb") and not os.environ.get("DISPLAY"):
        pytest.skip("NOT RUN: no display and no Xvfb (Debian: xvfb) for ParaView")
    r = subprocess.run([sys.executable, os.path.join(PARAVIEW, "headless.py"), PVBATCH,
                        os.path.join(PARAVIEW, "force_network.py"), str(run), str(png), "--height-mm", "15",
                        "--size", "300", "350"], capture_output=True, text=True, timeout=600)
    assert r.returncode != 0, r.stdout + r.stderr
    assert "F_n ranges over" in r.stdout + r.stderr and "not written" in r.stdout + r.stderr, r.stdout + r.stderr
    assert not png.exists() and not list(tmp_path.glob("*.tmp.png"))


def test_force_network_refuses_what_it_cannot_draw(example_runs, tmp_path):
    """Bad arguments and a damaged or missing run.xdmf end with a message and no picture (a damaged one
    aborted pvbatch, a missing one, --size 0 0 gave tracebacks, --height-mm nan drew snapshot 0)."""
    h5 = example_runs["pulloff"]
    run = tmp_path / "run"
    run.mkdir()
    os.symlink(h5, run / "run.h5")
    xdmf = open(os.path.join(os.path.dirname(h5), "run.xdmf")).read()
    png = tmp_path / "f.png"
    script = os.path.join(PARAVIEW, "force_network.py")

    def refused(args, message):
        # (the script checks these before it imports ParaView: the Python that runs the tests will do)
        r = subprocess.run([sys.executable, script, str(run), str(png), *args], capture_output=True, text=True,
                           timeout=120)
        out = r.stdout + r.stderr
        assert r.returncode != 0 and message in out and "Traceback" not in out, out
        assert not png.exists()

    refused([], "run.xdmf: no such file")
    (run / "run.xdmf").write_text(xdmf[: len(xdmf) // 2])
    refused([], "not an XDMF file dem2d wrote")
    (run / "run.xdmf").write_text(xdmf.replace("run.h5:/", "elsewhere.h5:/"))
    refused([], "not a dem2d run's XDMF")
    (run / "run.xdmf").write_text(xdmf)
    refused(["--size", "0", "0"], "--size 0 0: each must be from 16 to 16384 pixels")
    refused(["--height-mm", "nan"], "--height-mm nan: must be a finite height")
