"""The study's pipeline: the programs Make runs between the simulations and
the report, as one Python package. Run them as modules from the repository's
root, e.g.

    python3 -m pipeline.report.figures results/default

Shared pieces at the top: the stage registry (stages.py), reading and
writing files (files.py), the TOML writer (tomlwrite.py), the pull-off at
another speed (pull_speed.py).
"""
import sys
from pathlib import Path

# The run-file reader of this tree (python/dem2d), ahead of any installed one: a run file is read by the
# reader of the code that wrote it.
_READER = str(Path(__file__).resolve().parents[1] / "python")
if _READER not in sys.path:
    sys.path.insert(0, _READER)
