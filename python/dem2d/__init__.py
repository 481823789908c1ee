"""Read dem2d run files (run.h5) with h5py and numpy.

    import dem2d
    with dem2d.open_run("results/default/pulloff/run.h5") as run:
        print(run.parameters.name, run.end_time, "s,", run.n_particles, "grains")
        s = run.snapshot(-1)                      # the last snapshot
        xy, d = s.position, run.particles.diameter
        c = s.contacts
        on_intruder = c.body == run.body("intruder").index
        print(c.fn[on_intruder].sum(), "N/m on the intruder")
        t, f = run.series.time, run.series.body_force(run.body("intruder"))

Units are SI per unit depth (forces N/m, masses kg/m); every dataset's unit
and meaning are its `units` and `description` attributes (run.units(path),
run.description(path)). The layout: docs/run_file.md; this package: docs/python.md.
"""
from .checks import RunFileError
from .run import Body, Contacts, Run, Series, Snapshot, check_run, open_run

__all__ = ["Body", "Contacts", "Run", "RunFileError", "Series", "Snapshot", "check_run", "open_run"]
__version__ = "0.1.0"
