"""Reading the stages' files and writing outputs for the report scripts:
errors name the file and the make target that writes it; outputs appear
complete or not at all."""
import json
import os
import sys
from pathlib import Path

# the run-file reader (python/dem2d): the one way the scripts read run files


def fail(message: str) -> None:
    print(message, file=sys.stderr)
    sys.exit(2)


def read_json(path: Path, target: str) -> dict:
    """`target`: the make command that writes the file, e.g. "make cg PRESET=default"."""
    try:
        with open(path) as f:
            return json.load(f)
    except FileNotFoundError:
        fail(f"{path}: no such file: run `{target}`")
    except (OSError, json.JSONDecodeError) as e:  # (make would not remake a file that exists: delete it)
        fail(f"{path}: unreadable ({e}): delete it and run `{target}`")


def read_toml(path: Path) -> dict:
    import tomllib

    try:
        with open(path, "rb") as f:
            return tomllib.load(f)
    except (OSError, tomllib.TOMLDecodeError) as e:
        fail(f"{path}: {e}")


def write_atomic(path: Path, text: str) -> None:
    """`path` complete or not at all: written under a temporary name, then renamed. A failure (a full disk)
    removes the temporary and stops with the file and the reason (exit 2)."""
    tmp = Path(str(path) + ".tmp")
    try:
        tmp.write_text(text)
        os.replace(tmp, path)
    except OSError as e:
        tmp.unlink(missing_ok=True)
        fail(f"{path}: cannot write it ({e.strerror or e}); nothing was left half-written")


def write_if_changed(path: Path, text: str) -> bool:
    """Writes `text` to `path` (atomically, creating its folder) unless the file already holds it, so that
    make's rules depending on it stay up to date; True if it wrote."""
    path = Path(path)
    if path.exists() and path.read_text() == text:
        return False
    path.parent.mkdir(parents=True, exist_ok=True)
    write_atomic(path, text)
    return True


def stages() -> list:
    """The analysis stages of the registry (pipeline/stages.py): the Makefile's STAGE_REGISTRY, which it
    exports as DEM2D_STAGE_REGISTRY (an absolute path), else pipeline/stages.toml."""
    from pipeline.stages import REGISTRY, RegistryError, load

    try:
        return load(Path(os.environ.get("DEM2D_STAGE_REGISTRY") or REGISTRY))
    except RegistryError as e:
        fail(str(e))


def utf8(value):
    """GoogleTest's JSON writer escapes each byte of a UTF-8 string as its own code point."""
    if not isinstance(value, str):
        return value
    try:
        return value.encode("latin-1").decode("utf-8")
    except (UnicodeEncodeError, UnicodeDecodeError):
        return value


def check_rows(check: dict) -> list:
    """The tests of a check.json (check_paper_targets' GoogleTest JSON), one dict per target, text decoded."""
    return [{k: utf8(v) for k, v in t.items()} for suite in check.get("testsuites", []) for t in suite.get("testsuite", [])]
