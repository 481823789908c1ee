"""The paper's Fig. 6b in ParaView: the normal-force network of a pull-off at an
intruder height H (default 34 mm), read from the run's run.xdmf: grains as
discs, bodies as lines, every contact with F_n > 0 as a tube whose width and
colour grow with F_n. Headless (no window; ParaView here renders only through X,
so where there is no display headless.py gives it an Xvfb of its own):

    python3 pipeline/paraview/headless.py pvbatch pipeline/paraview/force_network.py RUN_DIR OUT.png
        [--height-mm 34] [--size 900 1200] [--reader T|S]

RUN_DIR holds run.h5 and run.xdmf. --reader: Xdmf3ReaderT (default; it names the
blocks particles, bodies, contacts) or Xdmf3ReaderS (what OpenDataFile picks; it
reads them as unnamed pieces of one dataset). Prints what the reader gave and what
it drew (snapshot, H, contacts); exits 1 if that differs from the run file.
"""
import argparse
import math
import os
import sys
from xml.etree import ElementTree

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path[:0] = [HERE, os.path.join(HERE, "..", "..", "python")]
import dem2d  # noqa: E402
from headless import require_display  # noqa: E402

pv = None  # paraview.simple: imported once the arguments and files are checked (the import takes seconds)

# each part's own array: how it is found where the reader keeps no block names (Xdmf3ReaderS)
OWN_ARRAY = {"particles": ["POINTS", "diameter"], "bodies": ["CELLS", "thickness"], "contacts": ["CELLS", "fn"]}


def part(reader, name):
    """particles, bodies or contacts: the block of that name (Xdmf3ReaderT), else the cells with its own array."""
    if reader.GetXMLName() == "Xdmf3ReaderT":
        return pv.ExtractBlock(Input=reader, Selectors=[f"/Root/{name}"])
    return pv.Threshold(Input=reader, Scalars=OWN_ARRAY[name], LowerThreshold=-1e300, UpperThreshold=1e300)


def block_names(reader, time):
    """The names of the reader's top blocks at `time` ("" for an unnamed one)."""
    reader.UpdatePipeline(time)
    data = pv.servermanager.Fetch(reader)
    if not data.IsA("vtkMultiBlockDataSet"):
        return []
    meta = [data.GetMetaData(i) if data.HasMetaData(i) else None for i in range(data.GetNumberOfBlocks())]
    return [m.Get(data.NAME()) if m is not None and m.Has(data.NAME()) else "" for m in meta]


MIN_PX, MAX_PX = 16, 16384  # a picture's side (ParaView fails on 0 and on what no X server can hold)


def check_xdmf(path):
    """run.xdmf as dem2d writes it (well-formed XML pointing into run.h5), or an exit naming it: ParaView's
    readers abort on a damaged one without a word."""
    if not os.path.isfile(path):
        sys.exit(f"force_network: {path}: no such file (dem2d run writes it beside run.h5)")
    try:
        root = ElementTree.parse(path).getroot()
    except (ElementTree.ParseError, OSError) as e:
        sys.exit(f"force_network: {path}: not an XDMF file dem2d wrote ({e})")
    items = [(d.text or "").strip() for d in root.iter("DataItem") if d.get("Format") == "HDF"]
    if root.tag != "Xdmf" or not items or not all(t.startswith("run.h5:/") for t in items):
        sys.exit(f"force_network: {path}: not a dem2d run's XDMF (its HDF data items do not all point into run.h5)")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("run_dir")
    ap.add_argument("out")
    ap.add_argument("--height-mm", type=float, default=34.0, help="intruder height H above the floor (mm)")
    ap.add_argument("--size", type=int, nargs=2, default=[900, 1200], metavar=("W", "H"),
                    help=f"pixels, each {MIN_PX} to {MAX_PX}")
    ap.add_argument("--reader", choices=["T", "S"], default="T", help="Xdmf3ReaderT or Xdmf3ReaderS")
    args = ap.parse_args()
    if not math.isfinite(args.height_mm):
        ap.error(f"--height-mm {args.height_mm}: must be a finite height (mm)")
    if not all(MIN_PX <= n <= MAX_PX for n in args.size):
        ap.error(f"--size {args.size[0]} {args.size[1]}: each must be from {MIN_PX} to {MAX_PX} pixels")
    h5 = os.path.abspath(os.path.join(args.run_dir, "run.h5"))
    xdmf = os.path.abspath(os.path.join(args.run_dir, "run.xdmf"))  # a bare name misleads the Xdmf3 readers
    check_xdmf(xdmf)
    require_display("force_network")
    global pv
    from paraview import simple as pv

    with dem2d.open_run(h5) as run:
        heights = run.heights() * 1e3
        k = int(abs(heights - args.height_mm).argmin())
        snap = run.snapshot(k)
        pressing = int((snap.contacts.fn > 0).sum())
        fn_max = float(snap.contacts.fn.max()) if len(snap.contacts) else 1.0
        fn_min = float(snap.contacts.fn[snap.contacts.fn > 0].min()) if pressing else 0.0
        d_mean = float(run.particles.diameter.mean())
        # the frame: the cell's width, the floor to just above the highest grain
        xy, r = snap.position[snap.active], run.particles.diameter[snap.active] / 2
        box = [(xy[:, 0] - r).min(), (xy[:, 0] + r).max(), run.floor_top(), (xy[:, 1] + r).max() + 2 * d_mean]
        # what run.xdmf shows of snapshot k (points, cells): a point per grain, K per body, 2 per contact
        _, B, K, _ = run.file["snapshots/body_vertices"].shape
        N, C = len(run.particles.diameter), len(snap.contacts)
        expected = {"particles": (N, N), "bodies": (B * K, B), "contacts": (2 * C, C)}

    reader = (pv.Xdmf3ReaderT if args.reader == "T" else pv.Xdmf3ReaderS)(FileName=[xdmf])
    reader.UpdatePipelineInformation()
    names = block_names(reader, snap.time)
    print(f"force_network: {reader.GetXMLName()}: top blocks {names}")
    parts = {name: part(reader, name) for name in OWN_ARRAY}
    found = {}
    for name, source in parts.items():
        source.UpdatePipeline(snap.time)
        info = source.GetDataInformation()
        found[name] = (info.GetNumberOfPoints(), info.GetNumberOfCells())
        print(f"force_network: {name}: {found[name][0]} points, {found[name][1]} cells (run file: "
              f"{expected[name][0]} points, {expected[name][1]} cells)")

    view = pv.CreateRenderView()
    view.ViewSize = args.size
    view.ViewTime = snap.time
    view.UseColorPaletteForBackground = 0
    view.Background = [1, 1, 1]
    view.OrientationAxesVisibility = 0
    view.CameraParallelProjection = 1

    grains = pv.Glyph(Input=parts["particles"], GlyphType="2D Glyph")
    grains.GlyphType.GlyphType = "Circle"
    grains.GlyphType.Filled = 1
    grains.ScaleArray = ["POINTS", "diameter"]
    grains.ScaleFactor = 1.0  # the circle's diameter is 1: scaled to the grain's
    grains.GlyphMode = "All Points"
    g = pv.Show(grains, view)
    g.ColorArrayName = ["POINTS", ""]
    g.DiffuseColor = g.AmbientColor = [0.9, 0.9, 0.9]

    strong = pv.Threshold(Input=parts["contacts"], Scalars=["CELLS", "fn"], LowerThreshold=1e-12,
                          UpperThreshold=1e300)
    tubes = pv.Tube(Input=pv.CellDatatoPointData(Input=pv.ExtractSurface(Input=strong)), Scalars=["POINTS", "fn"],
                    Radius=0.02 * d_mean, VaryRadius="By Scalar", RadiusFactor=12.0, NumberofSides=8)
    t = pv.Show(tubes, view)
    pv.ColorBy(t, ("POINTS", "fn"))
    lut = pv.GetColorTransferFunction("fn")
    lut.ApplyPreset("Inferno (matplotlib)", True)
    lut.InvertTransferFunction()
    lut.RescaleTransferFunction(0.0, fn_max)
    bar = pv.GetScalarBar(lut, view)
    bar.Title, bar.ComponentTitle = "F_n (N/m)", ""
    bar.TitleColor = bar.LabelColor = [0, 0, 0]
    t.SetScalarBarVisibility(view, True)

    b = pv.Show(parts["bodies"], view)
    b.ColorArrayName = ["POINTS", ""]
    b.DiffuseColor = b.AmbientColor = [0.12, 0.47, 0.71]
    b.LineWidth = 4.0

    title = pv.Text(Text=f"H = {heights[k]:.1f} mm, t = {snap.time:.2f} s: {pressing} contacts with F_n > 0")
    tt = pv.Show(title, view)
    tt.Color = [0, 0, 0]
    tt.WindowLocation = "Upper Center"

    pv.Render(view)  # the first render resets the camera: frame the bed after it
    centre = [(box[0] + box[1]) / 2, (box[2] + box[3]) / 2]
    view.CameraFocalPoint = centre + [0.0]
    view.CameraPosition = centre + [1.0]
    view.CameraViewUp = [0, 1, 0]
    aspect = args.size[0] / args.size[1]
    view.CameraParallelScale = 0.55 * max(box[3] - box[2], (box[1] - box[0]) / aspect)
    # what ParaView drew against the run file, before anything is written: the parts' sizes, the pressing
    # contacts and the range of their F_n (an fn array pointing at other data keeps the counts)
    strong.UpdatePipeline(snap.time)
    drawn = strong.GetDataInformation().GetNumberOfCells()
    lo, hi = strong.CellData["fn"].GetRange() if drawn else (0.0, 0.0)
    problems = []
    if found != expected:
        problems.append(f"ParaView read the parts {found}, the run file has {expected}")
    if drawn != pressing:
        problems.append(f"ParaView drew {drawn} pressing contacts, the run file has {pressing}")
    elif pressing and not (math.isclose(lo, fn_min, rel_tol=1e-6) and math.isclose(hi, fn_max, rel_tol=1e-6)):
        problems.append(f"ParaView's F_n ranges over [{lo:.6g}, {hi:.6g}] N/m, the run file's pressing contacts "
                        f"over [{fn_min:.6g}, {fn_max:.6g}] N/m")
    if problems:
        sys.exit(f"force_network: snapshot {k} of {xdmf}: " + "; ".join(problems) + f": {args.out} not written")
    root, ext = os.path.splitext(args.out)
    tmp = f"{root}.tmp{ext}"  # ParaView picks the format by the extension
    pv.SaveScreenshot(tmp, view, ImageResolution=args.size)
    os.replace(tmp, args.out)
    print(f"force_network: snapshot {k} (H = {heights[k]:.2f} mm, t = {snap.time:.4f} s): "
          f"{drawn} contacts with F_n > 0 drawn (run file: {pressing}), F_n {lo:.4g}-{hi:.4g} N/m -> {args.out}")


if __name__ == "__main__":
    try:
        main()
    except dem2d.RunFileError as e:
        sys.exit(f"force_network: {e}")
    except KeyboardInterrupt:
        sys.exit("force_network: interrupted: nothing written")
