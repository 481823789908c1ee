#!/usr/bin/python3
"""The Python reader's verdict on a run file, for make fuzz's `reader` class:
  py_reader.py RUN.h5   exit 0 (sound; a summary), 2 (refused: RunFileError,
the message on stderr); anything else escapes as a traceback (a defect)."""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent.parent / "python"))
import dem2d  # noqa: E402

try:
    print(dem2d.check_run(sys.argv[1]))
except dem2d.RunFileError as e:
    print(f"dem2d-python: {e}", file=sys.stderr)
    sys.exit(2)
