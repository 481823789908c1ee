"""make bench-compare: dem2d against LAMMPS on the same settled bed (docs/performance.md)."""
