"""Reading the stages' files and writing outputs for the report scripts:
errors name the file and the make target that writes it; outputs appear
complete or not at all."""
import json
import os
import sys
from pathlib import Path


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
    except (OSError, json.JSONDecodeError) as e:
        fail(f"{path}: unreadable ({e}): rerun `{target}`")


def read_toml(path: Path) -> dict:
    import tomllib

    try:
        with open(path, "rb") as f:
            return tomllib.load(f)
    except (OSError, tomllib.TOMLDecodeError) as e:
        fail(f"{path}: {e}")


def write_atomic(path: Path, text: str) -> None:
    tmp = Path(str(path) + ".tmp")
    tmp.write_text(text)
    os.replace(tmp, path)
