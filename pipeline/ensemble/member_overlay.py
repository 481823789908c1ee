"""The overlay that makes member K of an ensemble: the fill scene's grain
generators with their seeds moved by K (member 0 is the single run itself).

    python3 -m pipeline.ensemble.member_overlay FILL_SCENE K OUT.toml [OVERLAY ...]

The generators are taken from FILL_SCENE and the overlays the run applies
(the last one that gives [[generator]] wins, as in dem2d's overlay merge);
each keeps every key, its seed becomes seed + K * 1000003 (a prime step, so
members of different ensembles of one scene do not share seeds). Only the
grain arrangement changes (here: the diameters drawn onto the lattice), so
the members are independent realisations of the same study.
"""
import sys
import tomllib
from pathlib import Path

from pipeline.files import write_if_changed
from pipeline.tomlwrite import value as toml_value

SEED_STEP = 1000003


def fail(message: str) -> None:
    print(f"member_overlay: {message}", file=sys.stderr)
    sys.exit(2)


def main(argv: list) -> int:
    if len(argv) < 4:
        fail("usage: python3 -m pipeline.ensemble.member_overlay FILL_SCENE K OUT.toml [OVERLAY ...]")
    scene, out = Path(argv[1]), Path(argv[3])
    try:
        k = int(argv[2])
    except ValueError:
        fail(f"member index {argv[2]!r}: must be an integer >= 0")
    if k < 0:
        fail(f"member index {k}: must be >= 0")
    generators = None
    for path in [scene] + [Path(p) for p in argv[4:] if p]:
        try:
            with open(path, "rb") as f:
                doc = tomllib.load(f)
        except (OSError, tomllib.TOMLDecodeError) as e:
            fail(f"{path}: {e}")
        if "generator" in doc:
            generators = doc["generator"]
    if not generators:
        fail(f"{scene}: no [[generator]]: an ensemble needs grains drawn from a seed")
    lines = [f"# Ensemble member {k} of {scene}: its generators' seeds moved by {k} x {SEED_STEP}",
             "# (written by pipeline/ensemble/member_overlay.py)"]
    for g in generators:
        if not isinstance(g.get("seed"), int):
            fail(f"{scene}: a [[generator]] without an integer seed")
        lines.append("[[generator]]")
        for key, value in g.items():
            if key == "seed":
                value = value + k * SEED_STEP
            lines.append(f"{key} = {toml_value(value)}")
    # its own layout, values through the one writer: these bytes decide whether every member's fill is made again
    write_if_changed(out, "\n".join(lines) + "\n")  # unchanged: what depends on it stays up to date
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
