"""The paper's Fig. 6b in ParaView: the normal-force network of a pull-off at an
intruder height H (default 34 mm), read from the run's run.xdmf: grains as
discs, bodies as lines, every contact with F_n > 0 as a tube whose width and
colour grow with F_n. Headless (no window):

    pvbatch pipeline/paraview/force_network.py RUN_DIR OUT.png [--height-mm 34] [--size 900 1200]

(`xvfb-run -a -s "-screen 0 1280x1024x24" pvbatch ...` where there is no display: a 24-bit screen, the default 8 bits may have no OpenGL visual; make paraview does both).
RUN_DIR holds run.h5 and run.xdmf. Prints what it drew (snapshot, H, contacts).
"""
import argparse
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "python"))
import dem2d  # noqa: E402
from paraview import simple as pv  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("run_dir")
    ap.add_argument("out")
    ap.add_argument("--height-mm", type=float, default=34.0, help="intruder height H above the floor (mm)")
    ap.add_argument("--size", type=int, nargs=2, default=[900, 1200], metavar=("W", "H"), help="pixels")
    args = ap.parse_args()
    h5 = os.path.abspath(os.path.join(args.run_dir, "run.h5"))
    xdmf = os.path.abspath(os.path.join(args.run_dir, "run.xdmf"))  # a bare name misleads the Xdmf3 readers

    with dem2d.open_run(h5) as run:
        heights = run.heights() * 1e3
        k = int(abs(heights - args.height_mm).argmin())
        snap = run.snapshot(k)
        pressing = int((snap.contacts.fn > 0).sum())
        fn_max = float(snap.contacts.fn.max()) if len(snap.contacts) else 1.0
        d_mean = float(run.particles.diameter.mean())
        # the frame: the cell's width, the floor to just above the highest grain
        xy, r = snap.position[snap.active], run.particles.diameter[snap.active] / 2
        box = [(xy[:, 0] - r).min(), (xy[:, 0] + r).max(), run.floor_top(), (xy[:, 1] + r).max() + 2 * d_mean]
        run_has = {"bodies": len(run.bodies) > 0, "contacts": run.file["contacts/i"].shape[0] > 0}

    reader = pv.Xdmf3ReaderT(FileName=[xdmf])
    view = pv.CreateRenderView()
    view.ViewSize = args.size
    view.ViewTime = snap.time
    view.UseColorPaletteForBackground = 0
    view.Background = [1, 1, 1]
    view.OrientationAxesVisibility = 0
    view.CameraParallelProjection = 1

    # run.xdmf's collections in order: particles, bodies (if any), contacts (if any); the reader
    # numbers the blocks instead of naming them
    order = ["particles"] + (["bodies"] if run_has["bodies"] else []) + (["contacts"] if run_has["contacts"] else [])

    def block(name):
        return pv.ExtractBlock(Input=reader, Selectors=[f"/Root/Block{order.index(name)}"])

    grains = pv.Glyph(Input=block("particles"), GlyphType="2D Glyph")
    grains.GlyphType.GlyphType = "Circle"
    grains.GlyphType.Filled = 1
    grains.ScaleArray = ["POINTS", "diameter"]
    grains.ScaleFactor = 1.0  # the circle's diameter is 1: scaled to the grain's
    grains.GlyphMode = "All Points"
    g = pv.Show(grains, view)
    g.ColorArrayName = ["POINTS", ""]
    g.DiffuseColor = g.AmbientColor = [0.9, 0.9, 0.9]

    strong = pv.Threshold(Input=block("contacts"), Scalars=["CELLS", "fn"], LowerThreshold=1e-12,
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

    b = pv.Show(block("bodies"), view)
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
    pv.SaveScreenshot(args.out, view, ImageResolution=args.size)
    drawn = strong.GetDataInformation().GetNumberOfCells()
    print(f"force_network: snapshot {k} (H = {heights[k]:.2f} mm, t = {snap.time:.4f} s): "
          f"{drawn} contacts with F_n > 0 drawn (run file: {pressing}) -> {args.out}")
    if drawn != pressing:
        sys.exit(f"force_network: ParaView read {drawn} pressing contacts, the run file has {pressing}")


if __name__ == "__main__":
    main()
